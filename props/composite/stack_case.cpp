#include "props/composite/stack_case.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <istream>
#include <ostream>
#include <sstream>
#include <stdexcept>

namespace lockstep::props::composite {

float StackCase::value(int k, int px, int ch) const {
  const StackLayer& l = layers[size_t(k)];
  const size_t i = size_t(px) * 4 + size_t(ch);
  return is8() ? float(l.rgba8[i]) / 255.0f : l.rgba[i];
}

LayerStack StackCase::to_stack() const {
  validate();
  LayerStack s;
  s.order = order;
  s.storage = storage;
  s.early_stop = early_stop;
  s.source = "stack_case:" + generator;
  for (size_t k = 0; k < layers.size(); ++k) {
    Layer L;
    L.alpha = layers[k].alpha;
    L.image = Image(width, height);
    for (int px = 0; px < pixels(); ++px)
      for (int ch = 0; ch < 4; ++ch)
        L.image.rgba[size_t(px) * 4 + size_t(ch)] = value(int(k), px, ch);
    if (is8()) L.rgba8.assign(layers[k].rgba8.begin(), layers[k].rgba8.end());
    L.source = "layer" + std::to_string(k);
    s.layers.push_back(std::move(L));
  }
  return s;
}

StackCase StackCase::with_order(Order o) const {
  StackCase c = *this;
  c.order = o;
  return c;
}

StackCase StackCase::with_early_stop(bool e) const {
  StackCase c = *this;
  c.early_stop = e;
  return c;
}

void StackCase::validate() const {
  if (width < 1 || height < 1 || width * height > kMaxPixels)
    throw std::invalid_argument("stack case: size out of range");
  if (layers.empty() || int(layers.size()) > kMaxLayers)
    throw std::invalid_argument("stack case: layer count out of range");
  for (const StackLayer& l : layers) {
    const size_t n = size_t(pixels()) * 4;
    if (is8() ? l.rgba8.size() != n : l.rgba.size() != n)
      throw std::invalid_argument("stack case: layer size differs from W*H*4");
  }
}

std::string hexf(float x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%a", double(x));
  return buf;
}

std::string hex4(const float* v) {
  return "(" + hexf(v[0]) + ", " + hexf(v[1]) + ", " + hexf(v[2]) + ", " + hexf(v[3]) + ")";
}

std::string lev4(const uint8_t* v) {
  return "(" + std::to_string(v[0]) + ", " + std::to_string(v[1]) + ", " + std::to_string(v[2]) +
         ", " + std::to_string(v[3]) + ")";
}

void write_case(std::ostream& out, const StackCase& c) {
  out << "stack v1\n";
  out << "generator " << (c.generator.empty() ? "-" : c.generator) << "\n";
  out << "size " << c.width << " " << c.height << "\n";
  out << "order " << name_of(c.order) << "\n";
  out << "storage " << name_of(c.storage) << "\n";
  out << "early_stop " << (c.early_stop ? 1 : 0) << "\n";
  for (const StackLayer& l : c.layers) {
    out << "layer " << name_of(l.alpha) << "\n";
    for (int px = 0; px < c.pixels(); ++px) {
      for (int ch = 0; ch < 4; ++ch) {
        const size_t i = size_t(px) * 4 + size_t(ch);
        out << (ch ? " " : "") << (c.is8() ? std::to_string(l.rgba8[i]) : hexf(l.rgba[i]));
      }
      out << "\n";
    }
  }
  out << "end\n";
}

namespace {

[[noreturn]] void fail(const std::string& name, int line, const std::string& what) {
  throw std::runtime_error(name + ":" + std::to_string(line) + ": " + what);
}

float parse_float(const std::string& tok, const std::string& name, int line) {
  if (tok == "inf") return INFINITY;
  if (tok == "-inf") return -INFINITY;
  if (tok == "nan") return NAN;
  char* end = nullptr;
  const double d = std::strtod(tok.c_str(), &end);
  if (end == tok.c_str() || *end) fail(name, line, "not a number: " + tok);
  const float f = float(d);
  if (double(f) != d) fail(name, line, "not exactly a float: " + tok);
  return f;
}

}  // namespace

StackCase read_case(std::istream& in, const std::string& name) {
  StackCase c;
  std::string text;
  int line = 0;
  bool header = false, ended = false;
  auto next = [&](std::string& s) {
    while (std::getline(in, s)) {
      ++line;
      const size_t h = s.find('#');
      if (h != std::string::npos) s.erase(h);
      if (s.find_first_not_of(" \t\r") != std::string::npos) return true;
    }
    return false;
  };
  std::string s;
  while (!ended && next(s)) {
    std::istringstream ls(s);
    std::string key;
    ls >> key;
    if (!header) {
      std::string v;
      ls >> v;
      if (key != "stack" || v != "v1") fail(name, line, "expected 'stack v1'");
      header = true;
    } else if (key == "generator") {
      ls >> c.generator;
    } else if (key == "size") {
      if (!(ls >> c.width >> c.height)) fail(name, line, "size W H");
    } else if (key == "order") {
      std::string v;
      ls >> v;
      const auto o = parse_order(v);
      if (!o) fail(name, line, "order ftb|btf");
      c.order = *o;
    } else if (key == "storage") {
      std::string v;
      ls >> v;
      const auto st = parse_storage(v);
      if (!st) fail(name, line, "storage float|unorm8");
      c.storage = *st;
    } else if (key == "early_stop") {
      int e = 0;
      if (!(ls >> e)) fail(name, line, "early_stop 0|1");
      c.early_stop = e != 0;
    } else if (key == "layer") {
      std::string v;
      ls >> v;
      const auto a = parse_alpha(v);
      if (!a) fail(name, line, "layer straight|premultiplied");
      StackLayer L;
      L.alpha = *a;
      if (c.width < 1 || c.height < 1 || c.width * c.height > kMaxPixels)
        fail(name, line, "bad size");
      for (int px = 0; px < c.width * c.height; ++px) {
        if (!next(s)) fail(name, line, "missing pixel line");
        std::istringstream ps(s);
        for (int ch = 0; ch < 4; ++ch) {
          std::string tok;
          if (!(ps >> tok)) fail(name, line, "pixel needs 4 values");
          if (c.is8()) {
            char* end = nullptr;
            const long q = std::strtol(tok.c_str(), &end, 10);
            if (*end || q < 0 || q > 255) fail(name, line, "level 0..255: " + tok);
            L.rgba8.push_back(uint8_t(q));
          } else {
            L.rgba.push_back(parse_float(tok, name, line));
          }
        }
      }
      c.layers.push_back(std::move(L));
    } else if (key == "end") {
      ended = true;
    } else {
      fail(name, line, "unknown key " + key);
    }
  }
  if (!ended) fail(name, line, "missing 'end'");
  try {
    c.validate();
  } catch (const std::exception& e) {
    fail(name, line, e.what());
  }
  return c;
}

void showValue(const StackCase& c, std::ostream& os) {
  os << "\n";
  write_case(os, c);
}

}  // namespace lockstep::props::composite

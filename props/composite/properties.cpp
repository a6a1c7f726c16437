// lockstep props/composite: the compositing family's properties, for the driver.
//
// One property per (check, subject) of checks.h: <Check>.composite__<impl>, e.g.
// Accuracy.composite__simd, each over its check's generators (one_of); plus
// RoundTrip8Exhaustive.composite__<impl> (every (c, a) pair once) and the
// deliberately broken compositors of mutants.h (Mutants.composite__<bug>).
// Subjects come from the registry's composite family (checks.h: subjects_of).
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>

#include "props/composite/checks.h"
#include "props/composite/gen.h"
#include "props/composite/mutants.h"
#include "props/composite/oracle.h"
#include "props/property.h"
#include "reference/composite.h"

namespace lockstep::props::composite {

FamilyProperties properties(const Family& family, RunResources&);

namespace {

// "StraightVsPremultiplied" -> "straight_vs_premultiplied"
std::string snake(std::string_view camel) {
  std::string s;
  for (char ch : camel) {
    if (std::isupper(static_cast<unsigned char>(ch))) {
      if (!s.empty()) s += '_';
      s += char(std::tolower(static_cast<unsigned char>(ch)));
    } else {
      s += ch;
    }
  }
  return s;
}

bool is_bucket(const std::string& l) { return l.size() > 1 && l[0] == 'a' && std::isdigit(static_cast<unsigned char>(l[1])); }

// The driver's statistics: errors in float ulps or 8-bit levels; 8-bit losses
// counted per output-alpha bucket (ok outcomes carry their bucket as the label).
void annotate(Verdict& v, const StackCase& c) {
  for (Outcome& o : v.rays) {
    o.measured = o.kind != Outcome::skipped && std::isfinite(o.err);
    o.unit = c.is8() ? "8-bit levels" : "float ulps";
    if (is_bucket(o.label)) o.cls = o.label;
    else if (o.label.rfind("premul8_loss_", 0) == 0) o.cls = o.label.substr(13);
  }
}

std::string text_of(const StackCase& c) {
  std::ostringstream o;
  write_case(o, c);
  return o.str();
}

Property property(const NamedCheck& chk, const CompositeSubject& s) {
  Property p;
  p.family = "composite";
  p.check = snake(chk.name);
  p.suite = std::string(chk.name);
  p.name = "composite__" + s.name;
  p.generator = "stacks";  // one of the check's generators; the case records which
  p.pair = "composite";
  p.impl = s.name;
  p.bound = s.float_ulps;
  p.unit = "float ulps";
  p.units = "pixels";
  const auto gen = std::make_shared<const rc::Gen<StackCase>>(one_of(chk.generators));
  const CheckFn fn = chk.fn;
  p.run = [gen, fn, s] {
    auto c = std::make_shared<const StackCase>(**gen);
    Ran r;
    r.verdict = fn(s, *c);
    annotate(r.verdict, *c);
    r.text = [c](long) { return text_of(*c); };
    return r;
  };
  p.replay = [fn, s](const std::string& text, const std::string& file) {
    std::istringstream in(text);
    const StackCase c = read_case(in, file);
    Verdict v = fn(s, c);
    annotate(v, c);
    return v;
  };
  return p;
}

// Every (c, a) pair once, through the subject's own premultiply (a 256 x 256
// straight unorm8 layer), then ref::unpremultiply8: the loss is within
// round_trip8_bound(a) and the bound is attained (it is the least bound).
void round_trip_exhaustive(const CompositeSubject& s) {
  LayerStack st;
  Layer l;
  l.alpha = Alpha::straight;
  l.image = Image(256, 256);
  l.rgba8.resize(256 * 256 * 4);
  for (int a = 0; a < 256; ++a)
    for (int c = 0; c < 256; ++c) {
      uint8_t* q = &l.rgba8[size_t(a * 256 + c) * 4];
      q[0] = q[1] = q[2] = uint8_t(c);
      q[3] = uint8_t(a);
    }
  st.layers.push_back(l);
  st.storage = Storage::unorm8;
  FrameOptions o;
  o.width = o.height = 256;
  o.threads = 1;
  const Image out = s.fn(st, o, nullptr);
  int attained = 0, wrong = 0;
  long losses = 0;
  std::map<std::string, std::pair<long, long>> by;  // bucket -> (lost, all)
  for (int a = 1; a < 256; ++a) {
    int worst = 0;
    for (int c = 0; c < 256; ++c) {
      const float* p = &out.rgba[size_t(a * 256 + c) * 4];
      const long pq = std::lround(double(p[0]) * 255);
      if (float(pq) / 255.0f != p[0] || pq != nearest_mul255(c, a)) ++wrong;
      const Rgba8 back = ref::unpremultiply8({uint8_t(pq), uint8_t(pq), uint8_t(pq), uint8_t(a)});
      const int loss = std::abs(int(back.r) - c);
      worst = std::max(worst, loss);
      losses += loss > 0;
      auto& b = by[a < 16 ? "a1-15" : a < 64 ? "a16-63" : a < 128 ? "a64-127" : a < 255 ? "a128-254" : "a255"];
      b.first += loss > 0;
      ++b.second;
      EXPECT_LE(loss, round_trip8_bound(a)) << s.name << ": c " << c << " a " << a << " premultiplied " << pq;
    }
    attained += worst == round_trip8_bound(a);
  }
  EXPECT_EQ(wrong, 0) << s.name << ": premultiplied levels not correctly rounded";
  std::cout << "[ lockstep ] RoundTrip8Exhaustive." << s.name << ": " << wrong << " wrongly rounded of 65280; "
            << losses << " of 65280 (c, a > 0) pairs lose; bound floor(1/2 + 127.5/a) attained for " << attained
            << " of 255 alphas; loss rate by alpha:";
  for (const auto& [k, v] : by) std::cout << " " << k << " " << 100.0 * double(v.first) / double(v.second) << "%";
  std::cout << "\n";
}

}  // namespace

FamilyProperties properties(const Family& family, RunResources&) {
  FamilyProperties out;
  const std::vector<CompositeSubject> subjects = subjects_of(family);
  for (const NamedCheck& c : composite_checks())
    for (const CompositeSubject& s : subjects) {
      if (c.needs_reference_peer && s.is_reference) continue;
      out.properties.push_back(property(c, s));
    }
  for (const CompositeSubject& s : subjects)
    out.fixed.push_back({"RoundTrip8Exhaustive", "composite__" + s.name, [s] { round_trip_exhaustive(s); }});
  for (const composite::Mutant& m : mutants()) {
    props::Mutant pm{std::string(m.bug), std::string(m.what), snake(m.caught_by), {}};
    for (const NamedCheck& c : composite_checks()) {
      if (m.caught_by.empty() && c.needs_reference_peer) continue;  // agreement: the reference's own bugs
      pm.properties.push_back(property(c, m.subject));
    }
    out.mutants.push_back(std::move(pm));
  }
  return out;
}

}  // namespace lockstep::props::composite

// lockstep io: texture scenes (io/texture_scene.h).
#include "io/texture_scene.h"

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "io/image_io.h"
#include "io/text.h"
#include "io/tokenizer.h"

namespace lockstep {

namespace {

double srgb_to_linear(double c) {
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

long side_of(std::string_view w, const std::string& file, int line, const char* what) {
  long n = 0;
  if (!text::parse_long(w, n) || n < 1 || n > kMaxTextureSide)
    throw InputError(file, line,
                     std::string(what) + ": '" + std::string(w) + "' is not a size from 1 to " +
                         std::to_string(kMaxTextureSide));
  return n;
}

Texture blank(int w, int h, std::string name, const std::string& file, int line) {
  if (long(w) * long(h) > kMaxTexels)
    throw InputError(file, line,
                     "texture: " + std::to_string(w) + " x " + std::to_string(h) +
                         " texels is more than " + std::to_string(kMaxTexels) +
                         " (1 GiB of float RGBA)");
  Texture t;
  t.width = w;
  t.height = h;
  t.name = std::move(name);
  t.rgba.resize(size_t(w) * size_t(h) * 4);
  return t;
}

void put(Texture& t, int i, int j, double v) {
  float* p = t.rgba.data() + (size_t(j) * size_t(t.width) + size_t(i)) * 4;
  p[0] = p[1] = p[2] = float(v);
  p[3] = 1.0f;
}

}  // namespace

Texture procedural_texture(const std::string& spec, const std::string& file, int line) {
  const auto w = text::words(spec);
  if (w.empty())
    throw InputError(file, line, "texture: expected checker, zoneplate, noise or file");
  const std::string kind(w[0]);
  if (kind == "checker") {
    if (w.size() != 3) throw InputError(file, line, "texture checker: expected SIZE CELLS");
    const long n = side_of(w[1], file, line, "texture checker");
    long cells = 0;
    if (!text::parse_long(w[2], cells) || cells < 1 || cells > n)
      throw InputError(file, line,
                       "texture checker: CELLS '" + std::string(w[2]) + "' must be 1 to SIZE");
    Texture t = blank(int(n), int(n), spec, file, line);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) put(t, i, j, double(((i * cells) / n + (j * cells) / n) % 2));
    return t;
  }
  if (kind == "zoneplate") {
    if (w.size() != 2 && w.size() != 3)
      throw InputError(file, line, "texture zoneplate: expected SIZE [K]");
    const long n = side_of(w[1], file, line, "texture zoneplate");
    double k = 1;
    if (w.size() == 3 && (!text::parse_double(w[2], k) || !(k > 0) || k > 64))
      throw InputError(file, line,
                       "texture zoneplate: K '" + std::string(w[2]) + "' must be in (0, 64]");
    Texture t = blank(int(n), int(n), spec, file, line);
    // sin(A(x) + A(y)) with A(c) = pi K c^2 / n, by the sum formula: one sine
    // and cosine a row and a column, not one a texel.
    std::vector<double> sa(static_cast<size_t>(n)), ca(static_cast<size_t>(n));
    for (long i = 0; i < n; ++i) {
      const double c = i + 0.5 - 0.5 * double(n);
      const double a = M_PI * k * c * c / double(n);
      sa[size_t(i)] = std::sin(a);
      ca[size_t(i)] = std::cos(a);
    }
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        put(t, i, j, 0.5 + 0.5 * (sa[size_t(i)] * ca[size_t(j)] + ca[size_t(i)] * sa[size_t(j)]));
    return t;
  }
  if (kind == "noise") {
    if (w.size() != 3) throw InputError(file, line, "texture noise: expected SIZE SEED");
    const long n = side_of(w[1], file, line, "texture noise");
    long seed = 0;
    if (!text::parse_long(w[2], seed))
      throw InputError(file, line, "texture noise: SEED must be an integer");
    // 16 cosines with frequencies below 1/4 cycle a texel (band-limited: no
    // aliasing at level 0), directions and phases from a fixed generator.
    uint64_t s = uint64_t(seed) * 0x9E3779B97F4A7C15ull + 1;
    auto next = [&s] {
      s ^= s << 13;
      s ^= s >> 7;
      s ^= s << 17;
      return double(s >> 11) * 0x1.0p-53;
    };
    double fx[16], fy[16], ph[16];
    for (int k = 0; k < 16; ++k) {
      const double f = 0.25 * next(), ang = 2 * M_PI * next();
      fx[k] = f * std::cos(ang);
      fy[k] = f * std::sin(ang);
      ph[k] = 2 * M_PI * next();
    }
    Texture t = blank(int(n), int(n), spec, file, line);
    // cos(X(i) + Y(j)) = cos X cos Y - sin X sin Y: tables a row and a column.
    const size_t tab = static_cast<size_t>(16 * n);
    std::vector<double> cx(tab), sx(tab), cy(tab), sy(tab);
    for (int k = 0; k < 16; ++k)
      for (long i = 0; i < n; ++i) {
        const double x = 2 * M_PI * fx[k] * (i + 0.5) + ph[k], y = 2 * M_PI * fy[k] * (i + 0.5);
        cx[size_t(k * n + i)] = std::cos(x);
        sx[size_t(k * n + i)] = std::sin(x);
        cy[size_t(k * n + i)] = std::cos(y);
        sy[size_t(k * n + i)] = std::sin(y);
      }
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        double v = 0;
        for (int k = 0; k < 16; ++k)
          v += cx[size_t(k * n + i)] * cy[size_t(k * n + j)] -
               sx[size_t(k * n + i)] * sy[size_t(k * n + j)];
        put(t, i, j, 0.5 + v / 16);
      }
    return t;
  }
  throw InputError(file, line, "texture: '" + kind + "' is not checker, zoneplate, noise or file");
}

Texture texture_from_words(const std::string& spec, const std::string& folder,
                           const std::string& file, int line) {
  namespace fs = std::filesystem;
  std::vector<std::string> words;
  {
    std::istringstream ws(spec);
    for (std::string w; ws >> w;) words.push_back(w);
  }
  auto fail = [&](const std::string& m) { throw InputError(file, line, m); };
  if (words.empty()) fail("texture: expected checker, zoneplate, noise or file");
  if (words[0] == "file") {
    if (words.size() != 2 && words.size() != 3) fail("texture file: expected PATH [srgb|linear]");
    const std::string f(words[1]);
    const fs::path p = fs::path(f).is_absolute() ? fs::path(f) : fs::path(folder) / f;
    std::string space = words.size() == 3 ? words[2] : "";
    if (!space.empty() && space != "srgb" && space != "linear")
      fail("texture file: colour space '" + space + "' is not srgb or linear");
    Image img;
    try {
      img = read_image(p.string());
    } catch (const InputError& e) {
      fail(e.what());
    }
    if (img.width > kMaxTextureSide || img.height > kMaxTextureSide ||
        long(img.width) * long(img.height) > kMaxTexels)
      fail("texture file: " + std::to_string(img.width) + " x " + std::to_string(img.height) +
           " is larger than " + std::to_string(kMaxTextureSide) + " a side or " +
           std::to_string(kMaxTexels) + " texels");
    const std::string ext = text::lower(text::extension_of(f));
    if (space.empty())
      space = (ext == ".png" || ext == ".jpg" || ext == ".jpeg") ? "srgb" : "linear";
    std::vector<float> srgb8(256);
    for (int k = 0; k < 256; ++k) srgb8[size_t(k)] = float(srgb_to_linear(k / 255.0));
    Texture t;
    t.width = img.width;
    t.height = img.height;
    t.name = f;
    t.rgba.assign(img.rgba.begin(), img.rgba.end());
    for (size_t i = 0; i < t.rgba.size(); ++i) {
      if (!std::isfinite(t.rgba[i]))
        fail("texture file: texel (" + std::to_string((i / 4) % size_t(t.width)) + ", " +
             std::to_string((i / 4) / size_t(t.width)) + ") is not finite");
      if (space == "srgb" && i % 4 != 3) {
        // 8-bit files give k / 255: those from a table of the 256 levels.
        const float v = t.rgba[i];
        const long k = std::lround(double(v) * 255);
        t.rgba[i] = (k >= 0 && k <= 255 && float(double(k) / 255) == v) ? srgb8[size_t(k)]
                                                                        : float(srgb_to_linear(v));
      }
    }
    return t;
  }
  return procedural_texture(spec, file, line);
}

TextureScene parse_texture_scene(const std::string& text_in, const std::string& name,
                                 const std::string& folder) {
  namespace fs = std::filesystem;
  TextureScene sc;
  sc.source = name;
  sc.view.from = {0, 1, 3};
  sc.view.at = {0, 0, 0};
  sc.view.hither = 1e-3;
  bool have_texture = false, have_quad = false;
  std::string wrap = "repeat";
  int wrap_line = 0;
  text::Tokenizer in(text_in, name, {.comments = text::Comments::anywhere});
  auto numbers = [&](size_t n, const char* what) {
    in.expect_count(n + 1, what);
    std::vector<double> v(n);
    for (size_t i = 0; i < n; ++i) {
      if (!text::parse_double(in.words()[i + 1], v[i]) || !std::isfinite(v[i]))
        in.fail(std::string(what) + ": '" + std::string(in.words()[i + 1]) +
                "' is not a finite number");
    }
    return v;
  };
  auto vec = [&](const char* what) {
    const auto v = numbers(3, what);
    return Vec3{v[0], v[1], v[2]};
  };
  while (in.next()) {
    const std::string key(in.words()[0]);
    if (key == "texture") {
      sc.texture = texture_from_words(std::string(in.rest(1)), folder, name, in.line_no());
      have_texture = true;
    } else if (key == "wrap") {
      in.expect_count(2, "wrap");
      wrap = std::string(in.words()[1]);
      wrap_line = in.line_no();
    } else if (key == "quad") {
      const auto v = numbers(9, "quad");
      sc.origin = {v[0], v[1], v[2]};
      sc.edge_s = {v[3], v[4], v[5]};
      sc.edge_t = {v[6], v[7], v[8]};
      if (!(length(cross(sc.edge_s, sc.edge_t)) > 0))
        in.fail("quad: the edges S and T are parallel (no area)");
      have_quad = true;
    } else if (key == "repeat") {
      const auto v = numbers(2, "repeat");
      if (!(v[0] > 0 && v[1] > 0 && v[0] <= 1e6 && v[1] <= 1e6))
        in.fail("repeat: counts must be in (0, 1e6]");
      sc.repeat_u = v[0];
      sc.repeat_v = v[1];
    } else if (key == "from") {
      sc.view.from = vec("from");
    } else if (key == "at") {
      sc.view.at = vec("at");
    } else if (key == "up") {
      sc.view.up = vec("up");
    } else if (key == "angle") {
      const auto v = numbers(1, "angle");
      if (!(v[0] > 0 && v[0] < 180)) in.fail("angle: must be between 0 and 180 degrees");
      sc.view.angle = v[0];
    } else if (key == "hither") {
      const auto v = numbers(1, "hither");
      if (!(v[0] >= 0)) in.fail("hither: must be >= 0");
      sc.view.hither = v[0];
    } else if (key == "background") {
      sc.background = vec("background");
    } else if (key == "resolution") {
      in.expect_count(3, "resolution");
      long w = 0, h = 0;
      if (!text::parse_long(in.words()[1], w) || !text::parse_long(in.words()[2], h) || w < 1 ||
          h < 1 || w > kMaxTextureSide || h > kMaxTextureSide)
        in.fail("resolution: W and H must be 1 to " + std::to_string(kMaxTextureSide));
      sc.width = int(w);
      sc.height = int(h);
    } else {
      in.fail(
          "unknown keyword '" + key +
          "' (texture, wrap, quad, repeat, from, at, up, angle, hither, background, resolution)");
    }
  }
  if (!have_texture) throw InputError(name, 0, "no texture line");
  if (!have_quad) throw InputError(name, 0, "no quad line");
  if (wrap == "repeat")
    sc.texture.wrap = Wrap::repeat;
  else if (wrap == "clamp")
    sc.texture.wrap = Wrap::clamp;
  else if (wrap == "mirror")
    sc.texture.wrap = Wrap::mirror;
  else
    throw InputError(name, wrap_line, "wrap: '" + wrap + "' is not repeat, clamp or mirror");
  const Vec3 d = sc.view.at - sc.view.from;
  if (!(length(d) > 0)) throw InputError(name, 0, "from and at are the same point");
  if (!(length(cross(d, sc.view.up)) > 1e-12 * length(d) * length(sc.view.up)))
    throw InputError(name, 0, "up is parallel to the view direction (or zero)");
  return sc;
}

TextureScene read_texture_scene(const std::string& path) {
  const std::string text =
      text::read_text_file(path,
                           {.missing = "cannot read texture scene: no such file",
                            .folder = "cannot read texture scene: is a directory",
                            .unreadable = "cannot read texture scene: cannot open file",
                            .read_error = "cannot read texture scene: read error"},
                           text::kMaxListBytes);
  return parse_texture_scene(text, path, std::filesystem::path(path).parent_path().string());
}

}  // namespace lockstep

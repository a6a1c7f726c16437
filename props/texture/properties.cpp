// lockstep props/texture: the texture-filtering family's properties.
//
// Cases are small scenes (props/texture/case.h): a texture of 1-12 texels a
// side (random linear RGBA in [0, 1], or one colour), a wrap mode, a square
// quad on the plane y = 0 tiled 0.5-4 times, a camera above it looking at a
// point of it, 3-16 pixels a side, and one filter of core/texture.h.
//
//   Agreement.texture__<impl>  (part "agreement") the row's image equals the
//       reference's within kAgree per channel on every pixel, for every
//       filter (the simd row computes positions in double as the reference
//       does, colours in float: measured at most 1.8e-7 over 1000 cases);
//       our own rows count the same lookups as the reference.
//   Constant.texture__<impl>   (part "constant") a one-colour texture gives
//       that colour on every pixel whose centre sees the quad (and, for
//       supersampling, whose corners all do), under every filter and wrap
//       mode; the others show the background, exactly. Peers are judged on
//       the interior pixels only (their coverage of edge pixels is their
//       rasteriser's: GL's rules, float vertices).
//   BoxFilter.texture__<impl>  (part "oracle") area sampling against the
//       pixel's exact box filter (props/texture/oracle.h), interior pixels:
//       their difference is at most (r^3 - 1) (hi - lo) / 2 + kFloat, where
//       r is the footprint's largest over its smallest depth and [lo, hi]
//       the range of the texels it covers. Why: area sampling weights the
//       footprint's texels by texel area, the box filter by the area of their
//       image in the pixel, whose density is proportional to depth^-3; two
//       weightings whose densities differ by a factor at most r^3 differ in
//       total by at most r^3 - 1, and a difference of weightings summing to 0
//       moves the value by at most that times (hi - lo) / 2. So on an affine
//       view (camera square to the quad: r = 1) they are equal up to float
//       rounding; under perspective the row's error is the textbook method's,
//       bounded and measured (the largest |area - box| is printed).
//   Tiles.texture__<impl>      (part "tiles") a filter per tile (filter_tiles,
//       what error=E draws): every tile equals the same tile of the frame
//       drawn with its filter alone, exactly; frames of 2-3 x 2-3 tiles.
//   Rotation.texture__<impl>   (part "rotation") the texture turned a quarter
//       on the same quad re-parametrised (every point keeps its colour) gives
//       the same image within kAgree, for the filters continuous in their
//       positions (bilinear, trilinear, area, EWA); whole repeats, wrap repeat.
//   Lookups.texture__reference (part "pyramid") trilinear at a whole level k
//       equals bilinear in level k exactly; area sampling of a triangle inside
//       one texel gives that texel (within 1e-12).
//   Pyramid.texture__reference (part "pyramid") each mipmap level is the box
//       average of the one below (core/texture.h's rule, recomputed here from
//       the overlap of each coarse texel's extent with the fine texels: odd
//       sizes included), the last level is 1x1, and the level of detail is
//       monotone in the footprint's size.
#include <gtest/gtest.h>
#include <rapidcheck.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <string>

#include "props/gen/numbers.h"
#include "props/pixels.h"
#include "props/property.h"
#include "props/texture/case.h"
#include "props/texture/oracle.h"
#include "reference/texture_filter.h"

namespace lockstep::props::texture {

namespace {

constexpr double kAgree = 1e-5;   // simd against reference, per channel
constexpr double kFloat = 2e-6;   // float output of a value in [0, 1], with its sums
// A peer's rotation bound: each takes texture coordinates in float, so
// turning the texture moves a position, and a colour with it, by float
// rounding. OpenImageIO gets s = a / width in float, |s| <= 4 (the repeats):
// half an ulp of 4 is 2.4e-7, times 16 texels (the largest texture here),
// in both images: 7.6e-6 of a texel, so 1e-5 of a colour; measured over
// three deep runs (1000 cases each) at most 3.1e-6. llvmpipe interpolates
// its coordinates per fragment in float as well: measured at most 1.76e-5
// (p99 5.1e-6), bound 5e-5. GL would allow 8-bit bilinear weights (a step of
// 1/256 for a last-bit move); llvmpipe's are finer on these cases, and such
// a step would fail the bound, to be looked at, not widened.
double peer_rotation_bound(const FamilyImpl& impl) { return impl.name == "oiio" ? 1e-5 : 5e-5; }

const char* const kFilters[] = {"point", "bilinear", "area", "super2", "super4", "mip_nearest",
                                "trilinear", "aniso4", "aniso16", "ewa"};

enum class Kind { random, constant, affine, rotation, tiles };

rc::Gen<TexCase> case_gen(Kind kind, bool area_only) {
  return rc::gen::exec([kind, area_only] {
    TexCase c;
    TextureScene& sc = c.scene;
    Texture& t = sc.texture;
    // Half the textures have power-of-two sides (the simd row wraps those by
    // masks), the others any size (odd sizes: the pyramid's overlap weights).
    const bool pow2 = *gen::int_in(0, 1) == 1;
    t.width = pow2 ? 1 << *gen::int_in(0, 4) : int(*gen::int_in(1, 12));
    t.height = pow2 ? 1 << *gen::int_in(0, 4) : int(*gen::int_in(1, 12));
    t.wrap = kind == Kind::rotation ? Wrap::repeat : Wrap(*gen::int_in(0, 2));
    t.rgba.resize(size_t(t.width) * t.height * 4);
    if (kind == Kind::constant) {
      float v[4];
      for (float& x : v) x = float(*gen::uniform(0, 1));
      for (size_t i = 0; i < t.rgba.size(); ++i) t.rgba[i] = v[i % 4];
    } else {
      for (float& x : t.rgba) x = float(*gen::uniform(0, 1));
    }
    const double side = *gen::uniform(1, 8);
    sc.origin = {-side / 2, 0, -side / 2};
    sc.edge_s = {side, 0, 0};
    sc.edge_t = {0, 0, side};
    // The rotation's re-parametrised quad matches the original only for whole repeats.
    sc.repeat_u = kind == Kind::rotation ? double(*gen::int_in(1, 4)) : *gen::uniform(0.5, 4);
    sc.repeat_v = kind == Kind::rotation ? double(*gen::int_in(1, 4)) : *gen::uniform(0.5, 4);
    const double ax = *gen::uniform(-side / 3, side / 3), az = *gen::uniform(-side / 3, side / 3);
    sc.view.at = {ax, 0, az};
    if (kind == Kind::affine) {
      // Square to the quad: the map from texture to pixels is affine.
      sc.view.from = {ax, *gen::uniform(0.5, 4), az};
      sc.view.up = {0, 0, -1};
    } else {
      sc.view.from = {*gen::uniform(-side, side), *gen::uniform(0.1, 3), *gen::uniform(-side, side)};
      sc.view.up = {0, 1, 0};
      if (std::abs(sc.view.from.x - ax) + std::abs(sc.view.from.z - az) < 1e-3) sc.view.up = {0, 0, -1};
    }
    sc.view.angle = *gen::uniform(20, 80);
    sc.view.hither = 1e-3;
    sc.background = {0.25, 0.5, 0.75};
    sc.width = kind == Kind::tiles ? int(*gen::int_in(kFilterTileW + 1, 3 * kFilterTileW)) : int(*gen::int_in(3, 16));
    sc.height = kind == Kind::tiles ? int(*gen::int_in(kFilterTileH + 1, 3 * kFilterTileH)) : int(*gen::int_in(3, 16));
    if (kind == Kind::tiles) {
      // A filter per tile, each any of the family's.
      const int tiles = ((sc.width + kFilterTileW - 1) / kFilterTileW) * ((sc.height + kFilterTileH - 1) / kFilterTileH);
      for (int k = 0; k < tiles; ++k)
        c.tiles += (k ? " " : "") + std::string(kFilters[*gen::int_in(0, int(std::size(kFilters)) - 1)]);
    }
    static const char* const kContinuous[] = {"bilinear", "trilinear", "area", "ewa"};
    c.filter = area_only              ? "area"
               : kind == Kind::rotation ? kContinuous[*gen::int_in(0, 3)]
                                        : kFilters[*gen::int_in(0, int(std::size(kFilters)) - 1)];
    return c;
  });
}

Image run(const FamilyImpl& impl, const TexCase& c, FrameStats* stats = nullptr) {
  FrameOptions o;
  o.width = c.scene.width;
  o.height = c.scene.height;
  o.threads = 1;
  if (c.tiles.empty()) o.params.set("filter", c.filter);
  else o.params.set("filter_tiles", c.tiles);
  Input in = make_input<TextureScene>(c.scene, "case", o.width, o.height, c.scene.background);
  FrameStats st;
  Image img = impl.run_as<Image>(in, o, &st);
  if (stats) *stats = st;
  return img;
}

Verdict agreement(const FamilyImpl& ref, const FamilyImpl& impl, const TexCase& c) {
  FrameStats sa, sb;
  const Image a = run(ref, c, &sa), b = run(impl, c, &sb);
  Verdict v = compare_pixels(a, b, kAgree, "disagree", [&](int x, int y, double err) {
    return c.filter + " pixel (" + std::to_string(x) + ", " + std::to_string(y) + "): reference " +
           pixel_text(a.pixel(x, y)) + ", " + std::string(impl.name) + " " + pixel_text(b.pixel(x, y)) + ", error " +
           std::to_string(err) + " > " + std::to_string(kAgree);
  });
  // Our own rows count their lookups as the reference does (the pixels whose
  // centre sees the quad: the CLI's lookups per second); peers count theirs.
  if (impl.peer.empty() && sa.items != sb.items) {
    Outcome o;
    o.kind = Outcome::unexplained;
    o.label = "lookups";
    o.detail = c.filter + " " + std::to_string(c.scene.width) + " x " + std::to_string(c.scene.height) +
               ": reference counts " + std::to_string(sa.items) + " lookups, " + std::string(impl.name) + " " +
               std::to_string(sb.items);
    v.rays.push_back(o);
  }
  return v;
}

// A filter per tile: every tile of the frame equals the same tile of the
// frame drawn with that tile's filter alone, exactly (the same kernels on
// the same tiles).
Verdict tiles(const FamilyImpl& impl, const TexCase& c) {
  const Image planned = run(impl, c);
  Params p;
  p.set("filter_tiles", c.tiles);
  const TextureFilterPlan plan = texture_filter_plan(p, c.scene.width, c.scene.height, "case");
  // Each filter's frame alone, and from them the frame the plan should give.
  std::map<std::string, Image> alone;
  Image expected = planned;
  for (int y = 0; y < planned.height; ++y)
    for (int x = 0; x < planned.width; ++x) {
      const std::string& name = plan.at(x, y).name;
      if (!alone.count(name)) {
        TexCase one = c;
        one.tiles.clear();
        one.filter = name;
        alone[name] = run(impl, one);
      }
      std::copy_n(alone[name].pixel(x, y), 4, expected.pixel(x, y));
    }
  return compare_pixels(expected, planned, 0, "tile_differs", [&](int x, int y, double) {
    return "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") of a " + plan.at(x, y).name +
           " tile: alone " + pixel_text(expected.pixel(x, y)) + ", in the plan " + pixel_text(planned.pixel(x, y));
  });
}

// Whether impl can draw the case's filter (a peer's limits: FamilyImpl::unsupported).
bool draws(const FamilyImpl& impl, const TexCase& c) {
  Params p;
  p.set("filter", c.filter);
  return !impl.unsupported || impl.unsupported(p).empty();
}

Verdict not_drawn() {
  Verdict v;
  Outcome o;
  o.kind = Outcome::skipped;
  o.label = "unsupported_filter";
  v.rays.push_back(o);
  return v;
}

Verdict constant(const FamilyImpl& impl, const TexCase& c) {
  if (!draws(impl, c)) return not_drawn();
  const Image img = run(impl, c);
  const TexelMap map = TexelMap::make(c.scene, c.scene.width, c.scene.height);
  const float* colour = c.scene.texture.texel(0, 0);
  const float bg[4] = {float(c.scene.background.x), float(c.scene.background.y), float(c.scene.background.z), 1};
  const bool super = c.filter.rfind("super", 0) == 0;
  Verdict v;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      double a, b;
      const bool sees = map.texel_at(x + 0.5, y + 0.5, a, b) && map.on_quad(a, b);
      Outcome o;
      // Supersampling: some of the samples of an edge pixel may see the
      // background. A peer decides coverage by its own rules (GL's
      // rasterisation: top-left edges, float vertices): edge pixels are
      // coverage, not filtering.
      if ((sees && super) || !impl.peer.empty())
        if (!pixel_box_filter(c.scene, map, x, y).interior) {
          o.kind = Outcome::skipped;
          v.rays.push_back(o);
          continue;
        }
      const float* want = sees ? colour : bg;
      double err = 0;
      for (int k = 0; k < 4; ++k) err = std::max(err, double(std::abs(img.pixel(x, y)[k] - want[k])));
      if (!(err == err)) err = INFINITY;
      o.err = err;
      o.measured = true;
      const double bound = sees ? kFloat : 0.0;
      if (err > bound) {
        o.kind = Outcome::unexplained;
        o.label = sees ? "not_the_colour" : "not_the_background";
        o.detail = c.filter + " pixel (" + std::to_string(x) + ", " + std::to_string(y) + "): " +
                   pixel_text(img.pixel(x, y)) + ", expected " + pixel_text(want) + ", error " + std::to_string(err);
      }
      v.rays.push_back(std::move(o));
    }
  return v;
}

Verdict box_filter(const FamilyImpl& impl, const TexCase& c) {
  if (!draws(impl, c)) return not_drawn();
  const Image img = run(impl, c);
  const TexelMap map = TexelMap::make(c.scene, c.scene.width, c.scene.height);
  Verdict v;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const BoxValue box = pixel_box_filter(c.scene, map, x, y);
      Outcome o;
      if (!box.interior) {
        o.kind = Outcome::skipped;
        v.rays.push_back(o);
        continue;
      }
      if (std::abs(box.weight_sum - 1) > 1e-9) {
        o.kind = Outcome::unexplained;
        o.label = "oracle_weights";
        o.detail = "pixel (" + std::to_string(x) + ", " + std::to_string(y) + "): the oracle's weights sum to " +
                   std::to_string(box.weight_sum);
        v.rays.push_back(o);
        continue;
      }
      const double r3 = box.depth_ratio * box.depth_ratio * box.depth_ratio;
      double err = 0, worst_excess = -1;
      std::string why;
      for (int k = 0; k < 4; ++k) {
        const double e = std::abs(double(img.pixel(x, y)[k]) - box.rgba[size_t(k)]);
        const double bound = (r3 - 1) * (box.hi[size_t(k)] - box.lo[size_t(k)]) / 2 + kFloat;
        err = std::max(err, e);
        worst_excess = std::max(worst_excess, e - bound);
        if (e > bound)
          why = "channel " + std::to_string(k) + ": |" + std::to_string(img.pixel(x, y)[k]) + " - " +
                std::to_string(box.rgba[size_t(k)]) + "| > " + std::to_string(bound);
      }
      o.err = err;
      o.measured = true;
      if (!(err == err) || worst_excess > 0) {
        o.kind = Outcome::unexplained;
        o.label = "over_bound";
        o.detail = "pixel (" + std::to_string(x) + ", " + std::to_string(y) + "), depth ratio " +
                   std::to_string(box.depth_ratio) + ", " + std::to_string(box.texels) + " texels: " + why;
      } else if (err > kFloat) {
        o.kind = Outcome::explained;
        o.label = "perspective";  // within the derived bound: the textbook method's own error
      }
      v.rays.push_back(std::move(o));
    }
  return v;
}

Verdict pyramid(const TexCase& c) {
  const std::vector<Texture> levels = ref::build_pyramid(c.scene.texture);
  Verdict v;
  auto fail = [&](const std::string& d) {
    Outcome o;
    o.kind = Outcome::unexplained;
    o.label = "pyramid";
    o.detail = d;
    v.rays.push_back(o);
  };
  if (levels.back().width != 1 || levels.back().height != 1) fail("the last level is not 1x1");
  for (size_t k = 0; k + 1 < levels.size(); ++k) {
    const Texture& f = levels[k];
    const Texture& g = levels[k + 1];
    if (g.width != std::max(1, f.width / 2) || g.height != std::max(1, f.height / 2))
      fail("level " + std::to_string(k + 1) + " has the wrong size");
    // The coarse texel's extent [i r, (i+1) r] in fine texels, r = n / m; each
    // fine texel weighted by its overlap with it (recomputed here, not with
    // core's mip_box_weights).
    const double rx = double(f.width) / g.width, ry = double(f.height) / g.height;
    for (int j = 0; j < g.height; ++j)
      for (int i = 0; i < g.width; ++i) {
        double want[4] = {0, 0, 0, 0};
        for (int fj = 0; fj < f.height; ++fj) {
          const double oy = std::min(fj + 1.0, (j + 1) * ry) - std::max(double(fj), j * ry);
          if (oy <= 0) continue;
          for (int fi = 0; fi < f.width; ++fi) {
            const double ox = std::min(fi + 1.0, (i + 1) * rx) - std::max(double(fi), i * rx);
            if (ox <= 0) continue;
            for (int ch = 0; ch < 4; ++ch) want[ch] += ox * oy * f.texel(fi, fj)[ch] / (rx * ry);
          }
        }
        double err = 0;
        for (int ch = 0; ch < 4; ++ch) err = std::max(err, std::abs(want[ch] - g.texel(i, j)[ch]));
        Outcome o;
        o.err = err;
        o.measured = true;
        if (!(err <= kFloat)) {
          o.kind = Outcome::unexplained;
          o.label = "pyramid";
          o.detail = "level " + std::to_string(k + 1) + " texel (" + std::to_string(i) + ", " + std::to_string(j) +
                     "): " + pixel_text(g.texel(i, j)) + ", the box average is (" + std::to_string(want[0]) + " ...)";
        }
        v.rays.push_back(std::move(o));
      }
  }
  // The level of detail grows with the footprint: scaling its derivatives by s > 1.
  const double d[4] = {c.scene.origin.x, c.scene.view.angle / 30, c.scene.repeat_u - 2, c.scene.repeat_v};
  double last = ref::level_of_detail(d[0], d[1], d[2], d[3]);
  for (double s = 1.25; s < 100; s *= 1.25) {
    const double lod = ref::level_of_detail(s * d[0], s * d[1], s * d[2], s * d[3]);
    if (!(lod >= last)) fail("level of detail not monotone: " + std::to_string(lod) + " < " + std::to_string(last));
    last = lod;
  }
  return v;
}

// The texture turned a quarter (T'(i', j') = T(W-1-j', i'), H x W) on the
// same quad re-parametrised so that every point of it keeps its colour
// (origin O + S, edges T and -S, the repeats swapped): the image must not
// change. Filters that are continuous in the positions only (bilinear,
// trilinear, area, EWA: a last-bit difference of a position or a level moves
// the colour by as little); interior pixels (away from the quad's edges).
TexCase rotated(const TexCase& c) {
  TexCase r = c;
  const Texture& t = c.scene.texture;
  Texture& q = r.scene.texture;
  q.width = t.height;
  q.height = t.width;
  for (int j = 0; j < q.height; ++j)
    for (int i = 0; i < q.width; ++i)
      for (int ch = 0; ch < 4; ++ch)
        q.rgba[(size_t(j) * q.width + i) * 4 + ch] = t.texel(t.width - 1 - j, i)[ch];
  r.scene.origin = c.scene.origin + c.scene.edge_s;
  r.scene.edge_s = c.scene.edge_t;
  r.scene.edge_t = -c.scene.edge_s;
  r.scene.repeat_u = c.scene.repeat_v;
  r.scene.repeat_v = c.scene.repeat_u;
  return r;
}

Verdict rotation(const FamilyImpl& impl, const TexCase& c) {
  const double bound = impl.peer.empty() ? kAgree : peer_rotation_bound(impl);
  if (!draws(impl, c)) return not_drawn();
  const Image a = run(impl, c), b = run(impl, rotated(c));
  const TexelMap map = TexelMap::make(c.scene, c.scene.width, c.scene.height);
  Verdict v;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      Outcome o;
      if (!pixel_box_filter(c.scene, map, x, y).interior) {
        o.kind = Outcome::skipped;
        v.rays.push_back(o);
        continue;
      }
      double err = 0;
      for (int k = 0; k < 4; ++k) err = std::max(err, double(std::abs(a.pixel(x, y)[k] - b.pixel(x, y)[k])));
      if (!(err == err)) err = INFINITY;
      o.err = err;
      o.measured = true;
      if (err > bound) {
        o.kind = Outcome::unexplained;
        o.label = "rotation_changes_image";
        o.detail = c.filter + " pixel (" + std::to_string(x) + ", " + std::to_string(y) + "): " +
                   pixel_text(a.pixel(x, y)) + ", with the texture turned " + pixel_text(b.pixel(x, y));
      }
      v.rays.push_back(std::move(o));
    }
  return v;
}

// Single lookups of the reference: trilinear at a whole level is bilinear
// there, exactly; area sampling of a footprint inside one texel is that texel.
Verdict lookups(const TexCase& c) {
  const std::vector<Texture> levels = ref::build_pyramid(c.scene.texture);
  Verdict v;
  const double a0 = c.scene.view.from.x * 3.7 + c.scene.texture.width * 0.37;
  const double b0 = c.scene.view.from.z * 2.3 + c.scene.texture.height * 0.61;
  for (int k = 0; k < int(levels.size()); ++k) {
    const ref::Rgba tri = ref::lookup_trilinear(levels, double(k), a0, b0);
    const ref::Rgba bil = ref::lookup_bilinear(levels, k, a0, b0);
    Outcome o;
    o.measured = true;
    for (int ch = 0; ch < 4; ++ch) o.err = std::max(o.err, std::abs(tri[size_t(ch)] - bil[size_t(ch)]));
    if (o.err != 0) {
      o.kind = Outcome::unexplained;
      o.label = "trilinear_at_level";
      o.detail = "trilinear at level " + std::to_string(k) + " differs from bilinear there by " + std::to_string(o.err);
    }
    v.rays.push_back(o);
  }
  // A small triangle inside texel (i, j) (any integers: the wrap mode picks the texel).
  const int64_t i = int64_t(std::floor(a0)) - 7, j = int64_t(std::floor(b0)) + 5;
  const double fx = a0 - std::floor(a0), fy = b0 - std::floor(b0);
  const Polygon2 tri{{i + 0.1 + 0.3 * fx, j + 0.2}, {i + 0.9, j + 0.1 + 0.5 * fy}, {i + 0.4, j + 0.95}};
  const ref::Rgba avg = ref::average_over(c.scene.texture, tri);
  const float* want = c.scene.texture.wrapped(i, j);
  Outcome o;
  o.measured = true;
  for (int ch = 0; ch < 4; ++ch) o.err = std::max(o.err, std::abs(avg[size_t(ch)] - want[ch]));
  if (!(o.err <= 1e-12)) {
    o.kind = Outcome::unexplained;
    o.label = "area_inside_texel";
    o.detail = "area sampling of a triangle inside texel (" + std::to_string(i) + ", " + std::to_string(j) +
               ") is " + std::to_string(avg[0]) + " ..., the texel " + std::to_string(want[0]) + " ...";
  }
  v.rays.push_back(o);
  return v;
}

Property property(const Family& family, const FamilyImpl& impl, std::string suite, std::string check,
                  std::string generator, rc::Gen<TexCase> gen, std::function<Verdict(const TexCase&)> judge,
                  std::string unit) {
  return case_property<TexCase>(family, impl, std::move(suite), std::move(check), std::move(generator),
                                std::move(unit), "pixels", std::move(gen), std::move(judge), write_case, read_case);
}

}  // namespace

FamilyProperties properties(const Family& family, RunResources&) {
  FamilyProperties out;
  const FamilyImpl& ref = family.reference();
  for (const FamilyImpl& impl : family.impls) {
    const FamilyImpl* ip = &impl;
    // A peer computes by its own rules (OpenImageIO: its level of detail,
    // anisotropy and float coordinates): it is held to the oracle's and the
    // constant texture's exact answers, not to the reference's.
    if (family.has_property("agreement") && ip != &ref && impl.peer.empty()) {
      Property p = property(family, impl, "Agreement", "agreement", "texture_scene", case_gen(Kind::random, false),
                            [&ref, ip](const TexCase& c) { return agreement(ref, *ip, c); }, "channel difference");
      p.bound = kAgree;
      out.properties.push_back(std::move(p));
    }
    if (family.has_property("constant"))
      out.properties.push_back(property(family, impl, "Constant", "constant", "constant_texture",
                                        case_gen(Kind::constant, false),
                                        [ip](const TexCase& c) { return constant(*ip, c); }, "channel error"));
    if (family.has_property("oracle") && draws(impl, TexCase{{}, "area"})) {
      out.properties.push_back(property(family, impl, "BoxFilter", "box_filter", "texture_scene_area",
                                        case_gen(Kind::random, true),
                                        [ip](const TexCase& c) { return box_filter(*ip, c); },
                                        "channel error against the pixel's box filter"));
      Property p = property(family, impl, "BoxFilterAffine", "box_filter_affine", "texture_scene_affine",
                            case_gen(Kind::affine, true), [ip](const TexCase& c) { return box_filter(*ip, c); },
                            "channel error against the pixel's box filter");
      p.bound = kFloat;
      out.properties.push_back(std::move(p));
    }
    if (family.has_property("pyramid") && ip == &ref) {
      out.properties.push_back(property(family, impl, "Pyramid", "pyramid", "texture_scene",
                                        case_gen(Kind::random, false), pyramid, "texel error"));
      out.properties.push_back(property(family, impl, "Lookups", "lookups", "texture_scene",
                                        case_gen(Kind::random, false), lookups, "channel error"));
    }
    if (family.has_property("tiles") && impl.peer.empty()) {
      Property p = property(family, impl, "Tiles", "tiles", "texture_scene_tiles", case_gen(Kind::tiles, false),
                            [ip](const TexCase& c) { return tiles(*ip, c); }, "channel difference");
      p.bound = 0;
      out.properties.push_back(std::move(p));
    }
    if (family.has_property("rotation")) {
      Property p = property(family, impl, "Rotation", "rotation", "texture_scene_whole_repeats",
                            case_gen(Kind::rotation, false), [ip](const TexCase& c) { return rotation(*ip, c); },
                            "channel difference");
      p.bound = impl.peer.empty() ? kAgree : peer_rotation_bound(impl);
      out.properties.push_back(std::move(p));
    }
  }
  return out;
}

}  // namespace lockstep::props::texture

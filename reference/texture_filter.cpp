// Texture filtering, textbook version: from the texel to the footprint.
//
// Sources:
//  * The lecture notes' texture mapping: "Texel -> use texel color as diffuse
//    color"; "Area sampling: map corners of pixel, average texel colors";
//    "Supersampling"; "Mipmapping".
//  * L. Williams, "Pyramidal Parametrics", SIGGRAPH 1983: the mipmap and
//    trilinear interpolation between its levels.
//  * The OpenGL 4.6 specification, 8.14 "Texture Minification": the level of
//    detail rho = max(|d(u,v)/dx|, |d(u,v)/dy|) in texels, lambda = log2 rho,
//    the nearest level and linear blending between levels.
//  * EXT_texture_filter_anisotropic: N = min(ceil(Pmax / Pmin), maxAniso)
//    probes along the major axis, each at lambda = log2(Pmax / N).
//  * P. Heckbert, "Fundamentals of Texture Mapping and Image Warping", 1989,
//    and pbrt (Pharr, Jakob, Humphreys), 10.4.5 "Elliptically Weighted
//    Average": a Gaussian over the footprint's ellipse, on the level its minor
//    axis picks, its eccentricity clamped.
//
// Scalar, one pixel at a time, double precision, single-threaded. core/texture.h
// states the conventions (texel centres at half-integers, the mipmap rule).
#include "reference/texture_filter.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/timer.h"

namespace lockstep::ref {

namespace {

Rgba texel_value(const Texture& t, int64_t i, int64_t j) {
  const float* p = t.wrapped(i, j);
  return {p[0], p[1], p[2], p[3]};
}

Rgba mix(const Rgba& a, const Rgba& b, double t) {
  Rgba r;
  for (int c = 0; c < 4; ++c) r[c] = a[c] + t * (b[c] - a[c]);
  return r;
}

void add(Rgba& sum, const Rgba& v, double w) {
  for (int c = 0; c < 4; ++c) sum[c] += w * v[c];
}

Rgba scaled(const Rgba& v, double s) { return {v[0] * s, v[1] * s, v[2] * s, v[3] * s}; }

}  // namespace

// ---------------------------------------------------------------- the pyramid

std::vector<Texture> build_pyramid(const Texture& t) {
  std::vector<Texture> levels{t};
  while (levels.back().width > 1 || levels.back().height > 1) {
    const Texture& fine = levels.back();
    Texture coarse;
    coarse.width = mip_next_size(fine.width);
    coarse.height = mip_next_size(fine.height);
    coarse.wrap = fine.wrap;
    coarse.name = fine.name;
    coarse.rgba.resize(size_t(coarse.width) * coarse.height * 4);
    for (int j = 0; j < coarse.height; ++j)
      for (int i = 0; i < coarse.width; ++i) {
        // Each coarse texel is the box average of the fine texels it covers
        // (2 x 2 for even sizes; odd sizes weight the texels by their overlap).
        double wx[3], wy[3];
        const int fx = mip_box_weights(i, fine.width, coarse.width, wx);
        const int fy = mip_box_weights(j, fine.height, coarse.height, wy);
        Rgba sum{};
        for (int dy = 0; dy < 3; ++dy)
          for (int dx = 0; dx < 3; ++dx)
            if (wx[dx] > 0 && wy[dy] > 0) add(sum, texel_value(fine, fx + dx, fy + dy), wx[dx] * wy[dy]);
        float* out = coarse.rgba.data() + (size_t(j) * coarse.width + i) * 4;
        for (int c = 0; c < 4; ++c) out[c] = float(sum[c]);
      }
    levels.push_back(std::move(coarse));
  }
  return levels;
}

// ---------------------------------------------------------------- single lookups

Rgba lookup_point(const Texture& t, double a, double b) {
  // The texel whose square holds the point.
  return texel_value(t, int64_t(std::floor(a)), int64_t(std::floor(b)));
}

Rgba lookup_bilinear(const std::vector<Texture>& pyramid, int level, double a, double b) {
  const Texture& t = pyramid[size_t(level)];
  // The same (u, v) in this level's texel coordinates.
  const double la = a * t.width / pyramid[0].width;
  const double lb = b * t.height / pyramid[0].height;
  // Texel centres are at half-integers: measure from the centre below-left.
  const double x = la - 0.5, y = lb - 0.5;
  const double i0 = std::floor(x), j0 = std::floor(y);
  const double fx = x - i0, fy = y - j0;
  const int64_t i = int64_t(i0), j = int64_t(j0);
  // Two horizontal blends, then one vertical.
  const Rgba top = mix(texel_value(t, i, j), texel_value(t, i + 1, j), fx);
  const Rgba bottom = mix(texel_value(t, i, j + 1), texel_value(t, i + 1, j + 1), fx);
  return mix(top, bottom, fy);
}

double level_of_detail(double dadx, double dbdx, double dady, double dbdy) {
  // The longer of the pixel's two edges in texels (OpenGL's rho), as a level.
  const double rho = std::max(std::hypot(dadx, dbdx), std::hypot(dady, dbdy));
  return std::log2(rho);
}

Rgba lookup_trilinear(const std::vector<Texture>& pyramid, double lod, double a, double b) {
  const int last = int(pyramid.size()) - 1;
  // Magnification (a pixel smaller than a texel): the finest level.
  if (!(lod > 0)) return lookup_bilinear(pyramid, 0, a, b);
  if (lod >= last) return lookup_bilinear(pyramid, last, a, b);
  // Between two levels: bilinear in each, blended by the fraction.
  const int lo = int(std::floor(lod));
  const double t = lod - lo;
  return mix(lookup_bilinear(pyramid, lo, a, b), lookup_bilinear(pyramid, lo + 1, a, b), t);
}

Rgba lookup_aniso(const std::vector<Texture>& pyramid, int max_probes, double a, double b, double dadx, double dbdx,
                  double dady, double dbdy) {
  const double px = std::hypot(dadx, dbdx), py = std::hypot(dady, dbdy);
  const double pmax = std::max(px, py), pmin = std::min(px, py);
  // How many probes: the footprint's eccentricity, at most max_probes.
  int n = pmin > 0 ? int(std::ceil(pmax / pmin)) : max_probes;
  n = std::clamp(n, 1, max_probes);
  // Each probe covers a 1/n-th of the major axis: its level from that length.
  const double lod = std::log2(pmax / n);
  // The major axis, from one end of the footprint to the other.
  const double ax = px >= py ? dadx : dady, ay = px >= py ? dbdx : dbdy;
  Rgba sum{};
  for (int k = 0; k < n; ++k) {
    const double s = (k + 0.5) / n - 0.5;
    add(sum, lookup_trilinear(pyramid, lod, a + s * ax, b + s * ay), 1.0 / n);
  }
  return sum;
}

namespace {

// pbrt's EWA on one level: the ellipse's implicit form A u^2 + B u v + C v^2 < 1
// (texel units of that level), Gaussian weights exp(-alpha r^2) - exp(-alpha).
Rgba ewa_level(const std::vector<Texture>& pyramid, int level, double a, double b, double du0, double dv0,
               double du1, double dv1) {
  const int last = int(pyramid.size()) - 1;
  if (level >= last) return texel_value(pyramid[size_t(last)], 0, 0);
  const Texture& t = pyramid[size_t(level)];
  const double sx = double(t.width) / pyramid[0].width, sy = double(t.height) / pyramid[0].height;
  // The centre relative to texel centres, and the axes, in this level's texels.
  const double s = a * sx - 0.5, tt = b * sy - 0.5;
  du0 *= sx;
  du1 *= sx;
  dv0 *= sy;
  dv1 *= sy;
  // The ellipse's coefficients; the +1 keeps it at least a texel across.
  double A = dv0 * dv0 + dv1 * dv1 + 1;
  double B = -2 * (du0 * dv0 + du1 * dv1);
  double C = du0 * du0 + du1 * du1 + 1;
  const double inv_f = 1 / (A * C - B * B * 0.25);
  A *= inv_f;
  B *= inv_f;
  C *= inv_f;
  // Its bounding box.
  const double det = -B * B + 4 * A * C;
  const double inv_det = 1 / det;
  const double u_sqrt = std::sqrt(det * C), v_sqrt = std::sqrt(A * det);
  const int64_t s0 = int64_t(std::ceil(s - 2 * inv_det * u_sqrt)), s1 = int64_t(std::floor(s + 2 * inv_det * u_sqrt));
  const int64_t t0 = int64_t(std::ceil(tt - 2 * inv_det * v_sqrt)), t1 = int64_t(std::floor(tt + 2 * inv_det * v_sqrt));
  // The texels inside, weighted by the Gaussian of their distance.
  constexpr double kAlpha = 2;
  Rgba sum{};
  double weights = 0;
  for (int64_t it = t0; it <= t1; ++it) {
    const double v = it - tt;
    for (int64_t is = s0; is <= s1; ++is) {
      const double u = is - s;
      const double r2 = A * u * u + B * u * v + C * v * v;
      if (r2 < 1) {
        const double w = std::exp(-kAlpha * r2) - std::exp(-kAlpha);
        add(sum, texel_value(t, is, it), w);
        weights += w;
      }
    }
  }
  return weights > 0 ? scaled(sum, 1 / weights) : lookup_bilinear(pyramid, level, a, b);
}

}  // namespace

Rgba lookup_ewa(const std::vector<Texture>& pyramid, double max_eccentricity, double a, double b, double dadx,
                double dbdx, double dady, double dbdy) {
  // The two axes, the longer first.
  double du0 = dadx, dv0 = dbdx, du1 = dady, dv1 = dbdy;
  if (du0 * du0 + dv0 * dv0 < du1 * du1 + dv1 * dv1) {
    std::swap(du0, du1);
    std::swap(dv0, dv1);
  }
  const double major = std::hypot(du0, dv0);
  double minor = std::hypot(du1, dv1);
  // Too eccentric an ellipse would cover too many texels: widen its minor axis.
  if (minor * max_eccentricity < major && minor > 0) {
    const double scale = major / (minor * max_eccentricity);
    du1 *= scale;
    dv1 *= scale;
    minor *= scale;
  }
  if (minor == 0) return lookup_bilinear(pyramid, 0, a, b);
  // The minor axis picks the level; blend the two around it.
  const double lod = std::max(0.0, std::log2(minor));
  const int lo = int(std::floor(lod));
  const double t = lod - lo;
  return mix(ewa_level(pyramid, lo, a, b, du0, dv0, du1, dv1), ewa_level(pyramid, lo + 1, a, b, du0, dv0, du1, dv1),
             t);
}

// ---------------------------------------------------------------- area sampling

Rgba average_over(const Texture& t, const Polygon2& footprint) {
  Rgba sum{};
  if (footprint.size() < 3) return sum;
  double lo_y = footprint[0].y, hi_y = lo_y;
  for (const Point2& p : footprint) {
    lo_y = std::min(lo_y, p.y);
    hi_y = std::max(hi_y, p.y);
  }
  double total = 0;
  // One row of texels at a time: the footprint cut to the strip j <= b <= j+1 ...
  for (int64_t j = int64_t(std::floor(lo_y)); double(j) < hi_y; ++j) {
    const Polygon2 strip = clip_half_plane(clip_half_plane(footprint, 0, 1, -double(j)), 0, -1, double(j + 1));
    if (strip.size() < 3) continue;
    double lo_x = strip[0].x, hi_x = lo_x;
    for (const Point2& p : strip) {
      lo_x = std::min(lo_x, p.x);
      hi_x = std::max(hi_x, p.x);
    }
    // ... then to each texel i <= a <= i+1 of the row: the texel's colour
    // counts with the area it shares with the footprint.
    for (int64_t i = int64_t(std::floor(lo_x)); double(i) < hi_x; ++i) {
      const Polygon2 cell = clip_half_plane(clip_half_plane(strip, 1, 0, -double(i)), -1, 0, double(i + 1));
      const double area = std::abs(polygon_area(cell));
      if (area == 0) continue;
      add(sum, texel_value(t, i, j), area);
      total += area;
    }
  }
  return total > 0 ? scaled(sum, 1 / total) : sum;
}

// ---------------------------------------------------------------- the image

bool filter_pixel(const Texture& tex, const std::vector<Texture>& pyramid, const TexelMap& map,
                  const TextureFilterSettings& f, int x, int y, const Rgba& background, Rgba& c) {
  // The texel point the pixel's centre sees, if it sees the quad.
  double a, b;
  c = background;
  if (!map.texel_at(x + 0.5, y + 0.5, a, b) || !map.on_quad(a, b)) return false;
  double dadx, dbdx, dady, dbdy;
  map.derivatives(x + 0.5, y + 0.5, dadx, dbdx, dady, dbdy);
  switch (f.filter) {
    case TextureFilter::point:
      c = lookup_point(tex, a, b);
      break;
    case TextureFilter::bilinear:
      c = lookup_bilinear(pyramid, 0, a, b);
      break;
    case TextureFilter::area:
      c = average_over(tex, map.footprint(x, y));
      break;
    case TextureFilter::super: {
      // n x n point samples on a regular grid over the pixel square; a
      // sample that misses the quad sees the background.
      c = Rgba{};
      for (int sy = 0; sy < f.n; ++sy)
        for (int sx = 0; sx < f.n; ++sx) {
          double sa, sb;
          const bool hit =
              map.texel_at(x + (sx + 0.5) / f.n, y + (sy + 0.5) / f.n, sa, sb) && map.on_quad(sa, sb);
          add(c, hit ? lookup_point(tex, sa, sb) : background, 1.0 / (f.n * f.n));
        }
      break;
    }
    case TextureFilter::mip_nearest: {
      // OpenGL's nearest level: lambda <= 1/2 is level 0, else ceil(lambda + 1/2) - 1.
      const double lod = level_of_detail(dadx, dbdx, dady, dbdy);
      int level = lod <= 0.5 ? 0 : int(std::ceil(lod + 0.5)) - 1;
      level = std::min(level, int(pyramid.size()) - 1);
      c = lookup_bilinear(pyramid, level, a, b);
      break;
    }
    case TextureFilter::trilinear:
      c = lookup_trilinear(pyramid, level_of_detail(dadx, dbdx, dady, dbdy), a, b);
      break;
    case TextureFilter::aniso:
      c = lookup_aniso(pyramid, f.n, a, b, dadx, dbdx, dady, dbdy);
      break;
    case TextureFilter::ewa:
      c = lookup_ewa(pyramid, f.n, a, b, dadx, dbdx, dady, dbdy);
      break;
  }
  return true;
}

Image texture_filter(const TextureScene& scene, const FrameOptions& opts, FrameStats* stats) {
  const TextureFilterSettings f = texture_filter_settings(opts.params, scene.source);
  // A filter per tile, when the settings name one (error=E).
  const TextureFilterPlan plan = texture_filter_plan(opts.params, opts.width, opts.height, scene.source);
  const Texture& tex = scene.texture;
  if (tex.width < 1 || tex.height < 1) throw InputError(scene.source, 0, "empty texture");
  const TexelMap map = TexelMap::make(scene, opts.width, opts.height);
  // The mipmap, for the filters that use one (bilinear: level 0 alone, a copy).
  auto is_bilinear = [](TextureFilter g) { return g == TextureFilter::bilinear; };
  const bool mip = plan.tiles.empty() ? uses_pyramid(f.filter) : plan.uses(uses_pyramid);
  const bool level0 = plan.tiles.empty() ? is_bilinear(f.filter) : plan.uses(is_bilinear);
  // Timed apart (build_seconds): a one-shot cost, an application builds it once per texture.
  const Stopwatch build_watch;
  const std::vector<Texture> pyramid =
      mip ? build_pyramid(tex) : level0 ? std::vector<Texture>{tex} : std::vector<Texture>{};
  const double build_seconds = build_watch.seconds();
  const Rgba background{scene.background.x, scene.background.y, scene.background.z, 1};
  Image img(opts.width, opts.height);
  uint64_t lookups = 0;
  for (int y = 0; y < opts.height; ++y) {
    for (int x = 0; x < opts.width; ++x) {
      Rgba c;
      if (filter_pixel(tex, pyramid, map, plan.tiles.empty() ? f : plan.at(x, y), x, y, background, c)) ++lookups;
      float* p = img.pixel(x, y);
      for (int k = 0; k < 4; ++k) p[k] = float(c[k]);
    }
    if (opts.progress) opts.progress(double(y + 1) / opts.height);
  }
  if (stats) {
    stats->items = lookups;
    stats->build_seconds = build_seconds;
  }
  return img;
}

}  // namespace lockstep::ref

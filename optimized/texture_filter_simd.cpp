// lockstep optimized: texture filtering with Highway and TBB (optimized/texture_filter_simd.h).
#include "optimized/texture_filter_simd.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/error.h"
#include "core/large_buffer.h"
#include "hwy/highway.h"
#include "optimized/tiling.h"

namespace lockstep::opt::simd {

namespace {

namespace hn = hwy::HWY_NAMESPACE;
using D4 = hn::FixedTag<float, 4>;
using V4 = hn::Vec<D4>;

struct Level {
  int w = 0, h = 0;
  UninitVector<float> rgba;  // w * h * 4
};

struct Pyramid {
  std::vector<Level> levels;
  Wrap wrap = Wrap::repeat;
  double w0 = 1, h0 = 1;
};

HWY_INLINE int64_t wrap_fast(int64_t i, int64_t n, Wrap w) {
  if (uint64_t(i) < uint64_t(n)) return i;
  return wrap_index(i, n, w);
}

HWY_INLINE V4 fetch(const Level& l, int64_t i, int64_t j, Wrap w) {
  const D4 d;
  return hn::LoadU(d, l.rgba.data() + (size_t(wrap_fast(j, l.h, w)) * size_t(l.w) + size_t(wrap_fast(i, l.w, w))) * 4);
}

// The pyramid by core/texture.h's rule, a level's rows in parallel; the 2 x 2
// average of even sizes in vectors, odd sizes by their overlap weights.
Pyramid build_pyramid(const Texture& t, bool whole, int threads) {
  Pyramid p;
  p.wrap = t.wrap;
  p.w0 = t.width;
  p.h0 = t.height;
  Level base;
  base.w = t.width;
  base.h = t.height;
  base.rgba.resize(t.rgba.size());
  std::copy(t.rgba.begin(), t.rgba.end(), base.rgba.begin());
  p.levels.push_back(std::move(base));
  if (!whole) return p;
  const D4 d;
  while (p.levels.back().w > 1 || p.levels.back().h > 1) {
    const Level& fine = p.levels.back();
    Level coarse;
    coarse.w = mip_next_size(fine.w);
    coarse.h = mip_next_size(fine.h);
    coarse.rgba.resize(size_t(coarse.w) * coarse.h * 4);
    const bool even = fine.w % 2 == 0 && fine.h % 2 == 0 && coarse.w * 2 == fine.w && coarse.h * 2 == fine.h;
    parallel_tiles(coarse.w, coarse.h, coarse.w, 16, threads, {}, [&](int, int y0, int, int y1) {
      for (int j = y0; j < y1; ++j) {
        float* out = coarse.rgba.data() + size_t(j) * coarse.w * 4;
        if (even) {
          const float* r0 = fine.rgba.data() + size_t(2 * j) * fine.w * 4;
          const float* r1 = r0 + size_t(fine.w) * 4;
          const V4 q = hn::Set(d, 0.25f);
          for (int i = 0; i < coarse.w; ++i) {
            const V4 s = hn::Add(hn::Add(hn::LoadU(d, r0 + 8 * i), hn::LoadU(d, r0 + 8 * i + 4)),
                                 hn::Add(hn::LoadU(d, r1 + 8 * i), hn::LoadU(d, r1 + 8 * i + 4)));
            hn::StoreU(hn::Mul(s, q), d, out + 4 * i);
          }
        } else {
          double wy[3];
          const int fy = mip_box_weights(j, fine.h, coarse.h, wy);
          for (int i = 0; i < coarse.w; ++i) {
            double wx[3];
            const int fx = mip_box_weights(i, fine.w, coarse.w, wx);
            V4 s = hn::Zero(d);
            for (int dy = 0; dy < 3; ++dy)
              for (int dx = 0; dx < 3; ++dx)
                if (wx[dx] > 0 && wy[dy] > 0)
                  s = hn::MulAdd(fetch(fine, fx + dx, fy + dy, p.wrap), hn::Set(d, float(wx[dx] * wy[dy])), s);
            hn::StoreU(s, d, out + 4 * i);
          }
        }
      }
    });
    p.levels.push_back(std::move(coarse));
  }
  return p;
}

HWY_INLINE V4 point(const Pyramid& p, double a, double b) {
  return fetch(p.levels[0], int64_t(std::floor(a)), int64_t(std::floor(b)), p.wrap);
}

HWY_INLINE V4 bilinear(const Pyramid& p, int level, double a, double b) {
  const D4 d;
  const Level& l = p.levels[size_t(level)];
  const double x = a * l.w / p.w0 - 0.5, y = b * l.h / p.h0 - 0.5;
  const double i0 = std::floor(x), j0 = std::floor(y);
  const V4 fx = hn::Set(d, float(x - i0)), fy = hn::Set(d, float(y - j0));
  const int64_t i = int64_t(i0), j = int64_t(j0);
  const V4 t00 = fetch(l, i, j, p.wrap), t10 = fetch(l, i + 1, j, p.wrap);
  const V4 t01 = fetch(l, i, j + 1, p.wrap), t11 = fetch(l, i + 1, j + 1, p.wrap);
  const V4 top = hn::MulAdd(hn::Sub(t10, t00), fx, t00);
  const V4 bottom = hn::MulAdd(hn::Sub(t11, t01), fx, t01);
  return hn::MulAdd(hn::Sub(bottom, top), fy, top);
}

HWY_INLINE double lod_of(double dadx, double dbdx, double dady, double dbdy) {
  return std::log2(std::max(std::hypot(dadx, dbdx), std::hypot(dady, dbdy)));
}

HWY_INLINE V4 trilinear(const Pyramid& p, double lod, double a, double b) {
  const D4 d;
  const int last = int(p.levels.size()) - 1;
  if (!(lod > 0)) return bilinear(p, 0, a, b);
  if (lod >= last) return bilinear(p, last, a, b);
  const int lo = int(std::floor(lod));
  const V4 t = hn::Set(d, float(lod - lo));
  const V4 c0 = bilinear(p, lo, a, b), c1 = bilinear(p, lo + 1, a, b);
  return hn::MulAdd(hn::Sub(c1, c0), t, c0);
}

V4 aniso(const Pyramid& p, int max_probes, double a, double b, double dadx, double dbdx, double dady, double dbdy) {
  const D4 d;
  const double px = std::hypot(dadx, dbdx), py = std::hypot(dady, dbdy);
  const double pmax = std::max(px, py), pmin = std::min(px, py);
  int n = pmin > 0 ? int(std::ceil(pmax / pmin)) : max_probes;
  n = std::clamp(n, 1, max_probes);
  const double lod = std::log2(pmax / n);
  const double ax = px >= py ? dadx : dady, ay = px >= py ? dbdx : dbdy;
  V4 sum = hn::Zero(d);
  for (int k = 0; k < n; ++k) {
    const double s = (k + 0.5) / n - 0.5;
    sum = hn::Add(sum, trilinear(p, lod, a + s * ax, b + s * ay));
  }
  return hn::Mul(sum, hn::Set(d, 1.0f / float(n)));
}

V4 ewa_level(const Pyramid& p, int level, double a, double b, double du0, double dv0, double du1, double dv1) {
  const D4 d;
  const int last = int(p.levels.size()) - 1;
  if (level >= last) return fetch(p.levels[size_t(last)], 0, 0, p.wrap);
  const Level& l = p.levels[size_t(level)];
  const double sx = l.w / p.w0, sy = l.h / p.h0;
  const double s = a * sx - 0.5, tt = b * sy - 0.5;
  du0 *= sx;
  du1 *= sx;
  dv0 *= sy;
  dv1 *= sy;
  double A = dv0 * dv0 + dv1 * dv1 + 1;
  double B = -2 * (du0 * dv0 + du1 * dv1);
  double C = du0 * du0 + du1 * du1 + 1;
  const double inv_f = 1 / (A * C - B * B * 0.25);
  A *= inv_f;
  B *= inv_f;
  C *= inv_f;
  const double det = -B * B + 4 * A * C, inv_det = 1 / det;
  const double u_sqrt = std::sqrt(det * C), v_sqrt = std::sqrt(A * det);
  const int64_t s0 = int64_t(std::ceil(s - 2 * inv_det * u_sqrt)), s1 = int64_t(std::floor(s + 2 * inv_det * u_sqrt));
  const int64_t t0 = int64_t(std::ceil(tt - 2 * inv_det * v_sqrt)), t1 = int64_t(std::floor(tt + 2 * inv_det * v_sqrt));
  const float floor_w = std::exp(-2.0f);
  V4 sum = hn::Zero(d);
  float weights = 0;
  for (int64_t it = t0; it <= t1; ++it) {
    const double v = it - tt;
    for (int64_t is = s0; is <= s1; ++is) {
      const double u = is - s;
      const double r2 = A * u * u + B * u * v + C * v * v;
      if (r2 < 1) {
        const float w = std::exp(-2.0f * float(r2)) - floor_w;
        sum = hn::MulAdd(fetch(l, is, it, p.wrap), hn::Set(d, w), sum);
        weights += w;
      }
    }
  }
  return weights > 0 ? hn::Mul(sum, hn::Set(d, 1.0f / weights)) : bilinear(p, level, a, b);
}

V4 ewa(const Pyramid& p, double max_ecc, double a, double b, double dadx, double dbdx, double dady, double dbdy) {
  const D4 d;
  double du0 = dadx, dv0 = dbdx, du1 = dady, dv1 = dbdy;
  if (du0 * du0 + dv0 * dv0 < du1 * du1 + dv1 * dv1) {
    std::swap(du0, du1);
    std::swap(dv0, dv1);
  }
  const double major = std::hypot(du0, dv0);
  double minor = std::hypot(du1, dv1);
  if (minor * max_ecc < major && minor > 0) {
    const double scale = major / (minor * max_ecc);
    du1 *= scale;
    dv1 *= scale;
    minor *= scale;
  }
  if (minor == 0) return bilinear(p, 0, a, b);
  const double lod = std::max(0.0, std::log2(minor));
  const int lo = int(std::floor(lod));
  const V4 c0 = ewa_level(p, lo, a, b, du0, dv0, du1, dv1), c1 = ewa_level(p, lo + 1, a, b, du0, dv0, du1, dv1);
  return hn::MulAdd(hn::Sub(c1, c0), hn::Set(d, float(lod - lo)), c0);
}

// Area sampling: the footprint polygon (as the reference builds it) cut into
// texel rows; the texels wholly inside a row's span are summed without
// clipping, only the two ends of each row are clipped.
V4 area(const Pyramid& p, const TexelMap& map, int x, int y) {
  const D4 d;
  Polygon2 sq{{double(x), double(y)}, {double(x + 1), double(y)}, {double(x + 1), double(y + 1)}, {double(x), double(y + 1)}};
  const auto& m = map.to_texel.m;
  double far = 0;
  for (double a : {0.0, map.tex_w * map.repeat_u})
    for (double b : {0.0, map.tex_h * map.repeat_v})
      far = std::max(far, map.depth_row.x * a + map.depth_row.y * b + map.depth_row.z);
  sq = clip_half_plane(sq, m[6], m[7], m[8] - 1 / (2 * far));
  if (map.hither > 0) sq = clip_half_plane(sq, -m[6], -m[7], 1 / map.hither - m[8]);
  Polygon2 fp;
  for (const Point2& q : sq) {
    const Vec3 h = map.to_texel.apply(q.x, q.y);
    fp.push_back({h.x / h.z, h.y / h.z});
  }
  fp = clip_half_plane(fp, 1, 0, 0);
  fp = clip_half_plane(fp, -1, 0, map.tex_w * map.repeat_u);
  fp = clip_half_plane(fp, 0, 1, 0);
  fp = clip_half_plane(fp, 0, -1, map.tex_h * map.repeat_v);
  V4 sum = hn::Zero(d);
  if (fp.size() < 3) return sum;
  const Level& l = p.levels[0];
  double lo_y = fp[0].y, hi_y = lo_y;
  for (const Point2& q : fp) {
    lo_y = std::min(lo_y, q.y);
    hi_y = std::max(hi_y, q.y);
  }
  double total = 0;
  for (int64_t j = int64_t(std::floor(lo_y)); double(j) < hi_y; ++j) {
    const Polygon2 strip = clip_half_plane(clip_half_plane(fp, 0, 1, -double(j)), 0, -1, double(j + 1));
    if (strip.size() < 3) continue;
    double lo_x = strip[0].x, hi_x = lo_x;
    for (const Point2& q : strip) {
      lo_x = std::min(lo_x, q.x);
      hi_x = std::max(hi_x, q.x);
    }
    // Where the strip's polygon spans the whole texel row height: the x range
    // on both of its horizontal edges (a convex polygon holds the cell
    // [i, i+1] x [j, j+1] when it holds its four corners).
    double in_lo = -1e300, in_hi = 1e300;
    for (double yy : {double(j), double(j + 1)}) {
      double l0 = 1e300, h0 = -1e300;
      for (size_t k = 0, n = strip.size(); k < n; ++k) {
        const Point2& a0 = strip[k];
        const Point2& a1 = strip[(k + 1) % n];
        if ((a0.y - yy) * (a1.y - yy) > 0) continue;
        if (a0.y == a1.y) {
          if (a0.y == yy) {
            l0 = std::min({l0, a0.x, a1.x});
            h0 = std::max({h0, a0.x, a1.x});
          }
          continue;
        }
        const double xx = a0.x + (yy - a0.y) / (a1.y - a0.y) * (a1.x - a0.x);
        l0 = std::min(l0, xx);
        h0 = std::max(h0, xx);
      }
      in_lo = std::max(in_lo, l0);
      in_hi = std::min(in_hi, h0);
    }
    const int64_t full0 = int64_t(std::ceil(in_lo)), full1 = int64_t(std::floor(in_hi));  // cells [full0, full1)
    V4 row = hn::Zero(d);
    double row_area = 0;
    for (int64_t i = int64_t(std::floor(lo_x)); double(i) < hi_x; ++i) {
      if (i >= full0 && i + 1 <= full1) {
        if (i == full0) {
          for (int64_t k = full0; k < full1; ++k) row = hn::Add(row, fetch(l, k, j, p.wrap));
          row_area += double(full1 - full0);
        }
        continue;
      }
      const Polygon2 cell = clip_half_plane(clip_half_plane(strip, 1, 0, -double(i)), -1, 0, double(i + 1));
      const double ar = std::abs(polygon_area(cell));
      if (ar == 0) continue;
      row = hn::MulAdd(fetch(l, i, j, p.wrap), hn::Set(d, float(ar)), row);
      row_area += ar;
    }
    sum = hn::Add(sum, row);
    total += row_area;
  }
  return total > 0 ? hn::Mul(sum, hn::Set(d, float(1 / total))) : sum;
}

}  // namespace

Image texture_filter(const TextureScene& scene, const FrameOptions& opts, FrameStats* stats) {
  const TextureFilterSettings f = texture_filter_settings(opts.params, scene.source);
  const Texture& tex = scene.texture;
  if (tex.width < 1 || tex.height < 1) throw InputError(scene.source, 0, "empty texture");
  const TexelMap map = TexelMap::make(scene, opts.width, opts.height);
  const bool mip = f.filter == TextureFilter::mip_nearest || f.filter == TextureFilter::trilinear ||
                   f.filter == TextureFilter::aniso || f.filter == TextureFilter::ewa;
  const Pyramid pyr = build_pyramid(tex, mip, opts.threads);
  const D4 d;
  alignas(16) const float bg[4] = {float(scene.background.x), float(scene.background.y), float(scene.background.z), 1};
  const V4 background = hn::Load(d, bg);
  Image img = Image::uninitialized(opts.width, opts.height);
  std::atomic<uint64_t> lookups{0};
  parallel_tiles(opts.width, opts.height, 64, 16, opts.threads, opts.progress, [&](int x0, int y0, int x1, int y1) {
    uint64_t n = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) {
        double a, b;
        V4 c = background;
        if (map.texel_at(x + 0.5, y + 0.5, a, b) && map.on_quad(a, b)) {
          ++n;
          double dadx, dbdx, dady, dbdy;
          map.derivatives(x + 0.5, y + 0.5, dadx, dbdx, dady, dbdy);
          switch (f.filter) {
            case TextureFilter::point:
              c = point(pyr, a, b);
              break;
            case TextureFilter::bilinear:
              c = bilinear(pyr, 0, a, b);
              break;
            case TextureFilter::area:
              c = area(pyr, map, x, y);
              break;
            case TextureFilter::super: {
              V4 s = hn::Zero(d);
              for (int sy = 0; sy < f.n; ++sy)
                for (int sx = 0; sx < f.n; ++sx) {
                  double sa, sb;
                  const bool hit =
                      map.texel_at(x + (sx + 0.5) / f.n, y + (sy + 0.5) / f.n, sa, sb) && map.on_quad(sa, sb);
                  s = hn::Add(s, hit ? point(pyr, sa, sb) : background);
                }
              c = hn::Mul(s, hn::Set(d, 1.0f / float(f.n * f.n)));
              break;
            }
            case TextureFilter::mip_nearest: {
              const double lod = lod_of(dadx, dbdx, dady, dbdy);
              int level = lod <= 0.5 ? 0 : int(std::ceil(lod + 0.5)) - 1;
              level = std::min(level, int(pyr.levels.size()) - 1);
              c = bilinear(pyr, level, a, b);
              break;
            }
            case TextureFilter::trilinear:
              c = trilinear(pyr, lod_of(dadx, dbdx, dady, dbdy), a, b);
              break;
            case TextureFilter::aniso:
              c = aniso(pyr, f.n, a, b, dadx, dbdx, dady, dbdy);
              break;
            case TextureFilter::ewa:
              c = ewa(pyr, f.n, a, b, dadx, dbdx, dady, dbdy);
              break;
          }
        }
        hn::StoreU(c, d, img.pixel(x, y));
      }
    lookups += n;
  });
  if (stats) stats->items = lookups.load();
  return img;
}

}  // namespace lockstep::opt::simd

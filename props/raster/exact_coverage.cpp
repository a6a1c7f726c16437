// lockstep props/raster: the exact coverage oracle (see exact_coverage.h).
// Part of lockstep_oracle: the only raster file that includes CGAL.
#include "props/raster/exact_coverage.h"

#include <CGAL/Gmpq.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace lockstep::props::raster {

namespace {

using Q = CGAL::Gmpq;
struct P2 {
  Q x, y;
};
using Poly = std::vector<P2>;

// Twice the signed area (positive counter-clockwise in x right, y up terms;
// the sign only has to be consistent).
Q twice_area(const Poly& p) {
  Q a = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    const P2 &u = p[i], &v = p[(i + 1) % p.size()];
    a += u.x * v.y - u.y * v.x;
  }
  return a;
}

// Which side of the directed line a -> b point p is on (> 0: left).
Q side(const P2& a, const P2& b, const P2& p) { return (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x); }

// Sutherland-Hodgman: subject clipped by the convex polygon clipper (positive orientation).
Poly clip(const Poly& subject, const Poly& clipper) {
  Poly out = subject;
  for (size_t e = 0; e < clipper.size() && !out.empty(); ++e) {
    const P2 &a = clipper[e], &b = clipper[(e + 1) % clipper.size()];
    Poly in;
    in.swap(out);
    for (size_t i = 0; i < in.size(); ++i) {
      const P2 &p = in[i], &q = in[(i + 1) % in.size()];
      const Q sp = side(a, b, p), sq = side(a, b, q);
      if (sp >= 0) out.push_back(p);
      if ((sp > 0 && sq < 0) || (sp < 0 && sq > 0)) {
        const Q t = sp / (sp - sq);  // exact crossing
        out.push_back({p.x + t * (q.x - p.x), p.y + t * (q.y - p.y)});
      }
    }
  }
  return out;
}

Poly positive(Poly p) {
  if (twice_area(p) < 0) std::reverse(p.begin(), p.end());
  return p;
}

}  // namespace

Image exact_box_filtered(const std::vector<FlatTri>& tris_in, int width, int height, const Vec3& background) {
  if (tris_in.size() > 12) throw std::invalid_argument("exact_box_filtered: at most 12 triangles");
  std::vector<FlatTri> tris = tris_in;
  std::sort(tris.begin(), tris.end(), [](const FlatTri& a, const FlatTri& b) { return a.depth < b.depth; });
  std::vector<Poly> poly;
  for (const FlatTri& t : tris) poly.push_back(positive({{t.x[0], t.y[0]}, {t.x[1], t.y[1]}, {t.x[2], t.y[2]}}));

  Image img(width, height);
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i) {
      const Poly square = positive({{i, j}, {i + 1, j}, {i + 1, j + 1}, {i, j + 1}});
      // The triangles that touch this square (bounding boxes first: cheap).
      std::vector<size_t> touching;
      std::vector<Poly> in_square;
      for (size_t k = 0; k < tris.size(); ++k) {
        const FlatTri& t = tris[k];
        if (std::max({t.x[0], t.x[1], t.x[2]}) <= i || std::min({t.x[0], t.x[1], t.x[2]}) >= i + 1 ||
            std::max({t.y[0], t.y[1], t.y[2]}) <= j || std::min({t.y[0], t.y[1], t.y[2]}) >= j + 1)
          continue;
        Poly c = clip(square, poly[k]);
        if (c.size() < 3) continue;
        touching.push_back(k);
        in_square.push_back(std::move(c));
      }
      Vec3 color;
      Q covered = 0;
      for (size_t a = 0; a < touching.size(); ++a) {
        // Visible area of touching[a]: inclusion-exclusion over the nearer ones (indices < a).
        Q visible = 0;
        const size_t nearer = a;
        for (uint32_t subset = 0; subset < (1u << nearer); ++subset) {
          Poly p = in_square[a];
          for (size_t b = 0; b < nearer && p.size() >= 3; ++b)
            if (subset & (1u << b)) p = clip(p, poly[touching[b]]);
          if (p.size() < 3) continue;
          const Q area = twice_area(p) / 2;
          if (__builtin_popcount(subset) % 2) visible -= area;
          else visible += area;
        }
        covered += visible;
        color += CGAL::to_double(visible) * tris[touching[a]].color;
      }
      color += (1 - CGAL::to_double(covered)) * background;
      img.set(i, j, color);
    }
  return img;
}

}  // namespace lockstep::props::raster

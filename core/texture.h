// lockstep core: the texture-filtering family's contract (issue #32).
//
// Input: a texture on a planar quad seen by a pinhole camera
// (TextureScene). Output: an image. Every row computes, for each pixel whose
// centre sees the quad, one filtered texture value over that pixel's
// footprint; pixels whose centre misses it show the background.
//
// Conventions, stated once and used by every row:
//
// * Texels. A texture of W x H texels has texel (i, j) (column i, row j, row 0
//   the top of the file) covering the square [i, i+1] x [j, j+1] in *texel
//   coordinates*, its centre at (i + 1/2, j + 1/2). Texture coordinates (u, v)
//   in [0, 1]^2 are texel coordinates divided by (W, H). Outside [0, W) x
//   [0, H) the wrap mode picks the texel: repeat (i mod W), clamp (the edge
//   texel), mirror (... 1 0 | 0 1 ... W-1 | W-1 W-2 ...).
// * Texel values are linear float RGBA; files are converted to linear floats
//   when read (8-bit sRGB PNGs decoded by the sRGB curve), and every filter
//   works in linear values.
// * Pixels. Pixel (x, y) is the square [x, x+1] x [y, y+1] in *pixel
//   coordinates* (row 0 at the top); its centre (x + 1/2, y + 1/2) is the
//   Camera's centre of pixel (x, y) (core/camera.h: NFF's angle spans the
//   edge pixels' centres). A pixel's *footprint* is the preimage of that
//   square on the quad's plane, in texel coordinates: a quadrilateral, since
//   the map from the plane to the image is projective (TexelMap below).
// * The quad. P(s, t) = origin + s edge_s + t edge_t, (s, t) in [0, 1]^2,
//   carries texture coordinates (u, v) = (s repeat_u, t repeat_v): the
//   texture tiles repeat_u x repeat_v times across it (the wrap mode decides
//   what lies past u = 1).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/large_buffer.h"
#include "core/math.h"
#include "core/scene.h"

namespace lockstep {

enum class Wrap { repeat, clamp, mirror };

// The texel index a wrap mode gives coordinate index i on a side of n texels.
inline int64_t wrap_index(int64_t i, int64_t n, Wrap w) {
  switch (w) {
    case Wrap::repeat: {
      const int64_t r = i % n;
      return r < 0 ? r + n : r;
    }
    case Wrap::clamp:
      return i < 0 ? 0 : (i >= n ? n - 1 : i);
    case Wrap::mirror: {
      const int64_t p = 2 * n;
      int64_t r = i % p;
      if (r < 0) r += p;
      return r < n ? r : p - 1 - r;
    }
  }
  return 0;
}

// A texel grid: linear float RGBA, row 0 at the top.
struct Texture {
  int width = 0, height = 0;
  std::vector<float, NoInitAllocator<float>> rgba;  // width * height * 4
  Wrap wrap = Wrap::repeat;
  std::string name;  // "checker 256 8", or the file it came from

  const float* texel(int64_t i, int64_t j) const {
    return rgba.data() + (size_t(j) * size_t(width) + size_t(i)) * 4;
  }
  // The texel the wrap mode picks for indices (i, j), any integers.
  const float* wrapped(int64_t i, int64_t j) const { return texel(wrap_index(i, width, wrap), wrap_index(j, height, wrap)); }
};

// The family's input.
struct TextureScene {
  Texture texture;
  Vec3 origin{-1, 0, 0}, edge_s{2, 0, 0}, edge_t{0, 0, -2};  // the quad
  double repeat_u = 1, repeat_v = 1;
  View view;  // from, at, up, angle (NFF's convention), hither
  Vec3 background{0, 0, 0};
  int width = 256, height = 256;  // natural size (--size overrides)
  std::string source;
};

// A point of the plane, and a convex polygon (footprints).
struct Point2 {
  double x = 0, y = 0;
};
using Polygon2 = std::vector<Point2>;

// 3x3 matrix acting on homogeneous 2-vectors.
struct Homography {
  std::array<double, 9> m{};  // row-major
  // (x, y, 1) -> (X, Y, W)
  Vec3 apply(double x, double y) const {
    return {m[0] * x + m[1] * y + m[2], m[3] * x + m[4] * y + m[5], m[6] * x + m[7] * y + m[8]};
  }
  Homography inverse() const;
};

// The projective maps between pixel coordinates and the quad's texel
// coordinates, for one scene at one image size (exact up to rounding: built
// in double from the camera and the quad).
//   to_texel: (px, py, 1) -> (a, b, w): texel coordinates (a/w, b/w) of the
//             point of the quad's plane that pixel point sees; w > 0 exactly
//             where the ray meets the plane in front of the eye (w is the
//             reciprocal of the hit's depth, up to a constant factor).
//   to_pixel: the inverse, texel (a, b, 1) -> pixel (X, Y, W); W > 0 for
//             plane points in front of the eye (W is proportional to depth).
struct TexelMap {
  Homography to_texel, to_pixel;
  double tex_w = 1, tex_h = 1;  // the texture's size
  double repeat_u = 1, repeat_v = 1;
  double hither = 0;           // depth below which the plane is not seen
  Vec3 depth_row;              // depth of texel point (a, b) = depth_row . (a, b, 1)

  static TexelMap make(const TextureScene& scene, int width, int height);

  // Whether texel point (a, b) lies on the quad: 0 <= a <= W repeat_u, 0 <= b <= H repeat_v.
  bool on_quad(double a, double b) const { return a >= 0 && b >= 0 && a <= tex_w * repeat_u && b <= tex_h * repeat_v; }

  // The texel point pixel point (px, py) sees, false when its ray misses the
  // plane (parallel, behind the eye, nearer than hither).
  bool texel_at(double px, double py, double& a, double& b) const;

  // The derivatives of the texel point with respect to pixel x and y at
  // pixel point (px, py) (exact derivatives of the projective map: what a GPU
  // estimates by differences across a 2x2 quad of pixels). Valid where texel_at is.
  void derivatives(double px, double py, double& dadx, double& dbdx, double& dady, double& dbdy) const;

  // The footprint of pixel (x, y): its square mapped to texel coordinates,
  // clipped to the part of the plane in front of the eye (nearer than twice
  // the quad's farthest corner, no nearer than hither) and to the quad.
  Polygon2 footprint(int x, int y) const;
};

// The filters every row of the family offers (the `filter` setting).
enum class TextureFilter {
  point,      // the nearest texel to the pixel centre's texel point
  bilinear,   // bilinear between the four texels around it
  area,       // the average of the texels over the footprint (texture space)
  super,      // n x n point samples over the pixel square (supersampling)
  mip_nearest,// the mipmap level nearest the footprint's size, bilinear in it
  trilinear,  // the two levels around it, bilinear in each, blended
  aniso,      // N trilinear probes along the footprint's major axis
  ewa,        // Heckbert's elliptical weighted average (Gaussian), on the mipmap
};

struct TextureFilterSettings {
  TextureFilter filter = TextureFilter::trilinear;
  int n = 1;  // super: samples a side (2, 4, 8); aniso: the most probes (2..16); ewa: the largest eccentricity
  std::string name = "trilinear";  // as given: "super4", "aniso16"
};

// Parses "point", "bilinear", "area", "super2|4|8" (any 1..16), "mip_nearest",
// "trilinear", "aniso2|4|8|16" (any 1..64), "ewa" (eccentricity 8, pbrt's
// default) or "ewaN"; false on anything else.
bool parse_texture_filter(const std::string& s, TextureFilterSettings& out);
// The names --help lists.
inline constexpr const char* kTextureFilterNames =
    "point|bilinear|area|super2|super4|super8|mip_nearest|trilinear|aniso2|aniso4|aniso8|aniso16|ewa";
// Whether a filter reads the mipmap pyramid (mip_nearest, trilinear, aniso, ewa).
inline bool uses_pyramid(TextureFilter f) {
  return f == TextureFilter::mip_nearest || f == TextureFilter::trilinear || f == TextureFilter::aniso ||
         f == TextureFilter::ewa;
}

// A filter per tile: the frame cut into tiles of kFilterTileW x kFilterTileH
// pixels from its top-left corner (the last column and row of tiles may be
// narrower), row-major, each drawn with its own filter. The setting
// `filter_tiles` holds the names ("point trilinear aniso4 ...", one a tile);
// the family's error=E writes it (registry/texture_row.cpp), every row but
// the peers draws it.
inline constexpr int kFilterTileW = 64, kFilterTileH = 16;
struct TextureFilterPlan {
  int tiles_x = 0, tiles_y = 0;
  std::vector<TextureFilterSettings> tiles;  // empty: no plan
  const TextureFilterSettings& at(int x, int y) const {
    return tiles[size_t(y / kFilterTileH) * size_t(tiles_x) + size_t(x / kFilterTileW)];
  }
  bool uses(bool (*pred)(TextureFilter)) const {
    for (const TextureFilterSettings& t : tiles)
      if (pred(t.filter)) return true;
    return false;
  }
};

// The mipmap rule, stated once (every row builds its own pyramid by it).
// Level 0 is the texture. Level k+1 has max(1, floor(n_k / 2)) texels a side
// for n_k at level k (OpenGL's sizes); its texel i covers level k's texels
// [i r, (i+1) r] with r = n_k / n_{k+1} (r = 2 for even n_k: the 2x2 box
// average; for odd n_k, r = 2 + 1/n_{k+1} and each fine texel counts with the
// length of its overlap). The last level is 1x1. Lookups address level k
// with the same (u, v) in [0, 1], i.e. texel coordinates (u n_k, v m_k).
inline int mip_next_size(int n) { return n / 2 > 0 ? n / 2 : 1; }
// The weights of fine texels for coarse texel i on a side n -> m: first fine
// index and up to three weights (summing to 1).
inline int mip_box_weights(int i, int n, int m, double w[3]) {
  const double r = double(n) / m;
  const double lo = i * r, hi = (i + 1) * r;
  const int first = int(std::floor(lo));
  for (int k = 0; k < 3; ++k) {
    const double a = std::max(lo, double(first + k)), b = std::min(hi, double(first + k + 1));
    w[k] = b > a ? (b - a) / r : 0.0;
  }
  return first;
}

}  // namespace lockstep

namespace lockstep {

struct Params;
// The family's `filter` setting (default trilinear); InputError(source, 0,
// ...) naming the bad value.
TextureFilterSettings texture_filter_settings(const Params& params, const std::string& source);
// The plan in params' filter_tiles for a width x height frame; no tiles when
// it is not set. InputError(source, 0, ...) when malformed or of another size.
TextureFilterPlan texture_filter_plan(const Params& params, int width, int height, const std::string& source);

// ---------------------------------------------------------------- convex polygons
// Footprints are convex polygons (the projective image of a square, clipped by
// half-planes). Sutherland-Hodgman against one half-plane c0 x + c1 y + c2 >= 0.
inline Polygon2 clip_half_plane(const Polygon2& p, double c0, double c1, double c2) {
  Polygon2 out;
  const size_t n = p.size();
  for (size_t i = 0; i < n; ++i) {
    const Point2& a = p[i];
    const Point2& b = p[(i + 1) % n];
    const double fa = c0 * a.x + c1 * a.y + c2, fb = c0 * b.x + c1 * b.y + c2;
    if (fa >= 0) out.push_back(a);
    if ((fa >= 0) != (fb >= 0)) {
      const double t = fa / (fa - fb);
      out.push_back({a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)});
    }
  }
  return out;
}
// The shoelace area (positive for counter-clockwise in a y-up frame; callers take |.|).
inline double polygon_area(const Polygon2& p) {
  double s = 0;
  for (size_t i = 0, n = p.size(); i < n; ++i) {
    const Point2& a = p[i];
    const Point2& b = p[(i + 1) % n];
    s += a.x * b.y - a.y * b.x;
  }
  return 0.5 * s;
}

}  // namespace lockstep

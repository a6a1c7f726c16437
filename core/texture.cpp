// lockstep core: the texture family's projective maps and filter names (core/texture.h).
#include "core/texture.h"

#include <cstdlib>
#include <limits>

namespace lockstep {

Homography Homography::inverse() const {
  const auto& a = m;
  Homography r;
  // The adjugate over the determinant.
  r.m[0] = a[4] * a[8] - a[5] * a[7];
  r.m[1] = a[2] * a[7] - a[1] * a[8];
  r.m[2] = a[1] * a[5] - a[2] * a[4];
  r.m[3] = a[5] * a[6] - a[3] * a[8];
  r.m[4] = a[0] * a[8] - a[2] * a[6];
  r.m[5] = a[2] * a[3] - a[0] * a[5];
  r.m[6] = a[3] * a[7] - a[4] * a[6];
  r.m[7] = a[1] * a[6] - a[0] * a[7];
  r.m[8] = a[0] * a[4] - a[1] * a[3];
  const double det = a[0] * r.m[0] + a[1] * r.m[3] + a[2] * r.m[6];
  for (double& x : r.m) x /= det;
  return r;
}

TexelMap TexelMap::make(const TextureScene& scene, int width, int height) {
  const Camera cam = Camera::from_view(scene.view, width, height);
  TexelMap t;
  t.tex_w = scene.texture.width;
  t.tex_h = scene.texture.height;
  t.repeat_u = scene.repeat_u;
  t.repeat_v = scene.repeat_v;
  t.hither = scene.view.hither;
  // The plane's point at texel coordinates (a, b), relative to the eye:
  // q + a ea + b eb.
  const Vec3 ea = scene.edge_s / (t.tex_w * t.repeat_u);
  const Vec3 eb = scene.edge_t / (t.tex_h * t.repeat_v);
  const Vec3 q = scene.origin - cam.eye;
  // Camera coordinates (cx, cy, depth) of that point are linear in (a, b); the
  // pixel point is (cx / (depth pitch) + W/2, H/2 - cy / (depth pitch)), so
  // pixel = (X / depth, Y / depth) with X, Y, depth linear in (a, b).
  const double p = cam.pitch, hw = 0.5 * width, hh = 0.5 * height;
  auto row_x = [&](const Vec3& e) { return dot(e, cam.right) / p + dot(e, cam.forward) * hw; };
  auto row_y = [&](const Vec3& e) { return -dot(e, cam.up) / p + dot(e, cam.forward) * hh; };
  t.to_pixel.m = {row_x(ea), row_x(eb), row_x(q),  //
                  row_y(ea), row_y(eb), row_y(q),  //
                  dot(ea, cam.forward), dot(eb, cam.forward), dot(q, cam.forward)};
  t.depth_row = {t.to_pixel.m[6], t.to_pixel.m[7], t.to_pixel.m[8]};
  // The inverse maps (px, py, 1) to (a, b, 1) / depth: its third coordinate
  // is 1/depth, positive in front of the eye.
  t.to_texel = t.to_pixel.inverse();
  return t;
}

bool TexelMap::texel_at(double px, double py, double& a, double& b) const {
  const Vec3 h = to_texel.apply(px, py);
  if (!(h.z > 0) || !std::isfinite(h.z)) return false;
  if (1.0 / h.z < hither) return false;
  a = h.x / h.z;
  b = h.y / h.z;
  return std::isfinite(a) && std::isfinite(b);
}

void TexelMap::derivatives(double px, double py, double& dadx, double& dbdx, double& dady, double& dbdy) const {
  const auto& m = to_texel.m;
  const Vec3 h = to_texel.apply(px, py);
  const double iw2 = 1.0 / (h.z * h.z);
  // d(A/w)/dx = (A_x w - A w_x) / w^2, A_x = m[0], w_x = m[6].
  dadx = (m[0] * h.z - h.x * m[6]) * iw2;
  dbdx = (m[3] * h.z - h.y * m[6]) * iw2;
  dady = (m[1] * h.z - h.x * m[7]) * iw2;
  dbdy = (m[4] * h.z - h.y * m[7]) * iw2;
}

Polygon2 TexelMap::footprint(int x, int y) const {
  // The pixel square, in pixel coordinates.
  Polygon2 square{{double(x), double(y)}, {double(x + 1), double(y)}, {double(x + 1), double(y + 1)},
                  {double(x), double(y + 1)}};
  // Keep the part that sees the plane in front of the eye, no nearer than
  // hither and no farther than twice the quad's farthest corner (past that
  // the plane holds no quad; the pixel's rays above the horizon map to
  // points behind the eye): 1/w is the depth.
  const auto& m = to_texel.m;
  double far = 0;
  for (double a : {0.0, tex_w * repeat_u})
    for (double b : {0.0, tex_h * repeat_v})
      far = std::max(far, depth_row.x * a + depth_row.y * b + depth_row.z);
  square = clip_half_plane(square, m[6], m[7], m[8] - 1 / (2 * far));  // w >= 1 / (2 far)
  if (hither > 0) square = clip_half_plane(square, -m[6], -m[7], 1 / hither - m[8]);  // w <= 1 / hither
  // Map each corner to texel coordinates: a projective map keeps lines straight,
  // so the footprint is the polygon of the mapped corners.
  Polygon2 poly;
  for (const Point2& p : square) {
    const Vec3 h = to_texel.apply(p.x, p.y);
    poly.push_back({h.x / h.z, h.y / h.z});
  }
  // Only the quad carries the texture.
  poly = clip_half_plane(poly, 1, 0, 0);
  poly = clip_half_plane(poly, -1, 0, tex_w * repeat_u);
  poly = clip_half_plane(poly, 0, 1, 0);
  poly = clip_half_plane(poly, 0, -1, tex_h * repeat_v);
  return poly;
}

bool parse_texture_filter(const std::string& s, TextureFilterSettings& out) {
  auto number_after = [&](size_t prefix, int lo, int hi, int& n) {
    if (s.size() == prefix) return false;
    for (size_t i = prefix; i < s.size(); ++i)
      if (s[i] < '0' || s[i] > '9' || i - prefix > 3) return false;
    n = std::atoi(s.c_str() + prefix);
    return n >= lo && n <= hi;
  };
  TextureFilterSettings f;
  f.name = s;
  if (s == "point") f.filter = TextureFilter::point;
  else if (s == "bilinear") f.filter = TextureFilter::bilinear;
  else if (s == "area") f.filter = TextureFilter::area;
  else if (s == "mip_nearest") f.filter = TextureFilter::mip_nearest;
  else if (s == "trilinear") f.filter = TextureFilter::trilinear;
  else if (s == "ewa") {
    f.filter = TextureFilter::ewa;
    f.n = 8;
  } else if (s.rfind("super", 0) == 0) {
    f.filter = TextureFilter::super;
    if (!number_after(5, 1, 16, f.n)) return false;
  } else if (s.rfind("aniso", 0) == 0) {
    f.filter = TextureFilter::aniso;
    if (!number_after(5, 1, 64, f.n)) return false;
  } else if (s.rfind("ewa", 0) == 0) {
    f.filter = TextureFilter::ewa;
    if (!number_after(3, 1, 64, f.n)) return false;
  } else
    return false;
  out = f;
  return true;
}

}  // namespace lockstep

#include <sstream>

#include "core/error.h"
#include "core/family.h"

namespace lockstep {

TextureFilterSettings texture_filter_settings(const Params& params, const std::string& source) {
  const std::string s = params.get("filter", "trilinear");
  TextureFilterSettings f;
  if (!parse_texture_filter(s, f))
    throw InputError(source, 0,
                     "filter: '" + s + "' is not a texture filter (" + kTextureFilterNames +
                         "; superN for N = 1..16, anisoN for N = 1..64, ewaN for N = 1..64)");
  return f;
}

TextureFilterPlan texture_filter_plan(const Params& params, int width, int height, const std::string& source) {
  TextureFilterPlan plan;
  if (!params.has("filter_tiles")) return plan;
  plan.tiles_x = (width + kFilterTileW - 1) / kFilterTileW;
  plan.tiles_y = (height + kFilterTileH - 1) / kFilterTileH;
  std::istringstream words(params.get("filter_tiles"));
  for (std::string w; words >> w;) {
    TextureFilterSettings f;
    if (!parse_texture_filter(w, f)) throw InputError(source, 0, "filter_tiles: '" + w + "' is not a texture filter");
    plan.tiles.push_back(f);
  }
  if (plan.tiles.size() != size_t(plan.tiles_x) * size_t(plan.tiles_y))
    throw InputError(source, 0,
                     "filter_tiles: " + std::to_string(plan.tiles.size()) + " filters for " +
                         std::to_string(plan.tiles_x) + " x " + std::to_string(plan.tiles_y) + " tiles");
  return plan;
}

}  // namespace lockstep

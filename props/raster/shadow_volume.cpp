// lockstep props/raster: shadow volumes (reference/shadow_volume.h) against
// shadow rays (issue #22).
//
//   ShadowVolumes.zbuffer__reference   Random triangle scenes (shadow_scene: a
//       floor quad, 1..4 closed occluders -- boxes and tetrahedra, some turned
//       inside out, one sometimes with a triangle flipped (inconsistent) or a
//       face missing (open) -- and 0..3 loose triangles, some two-sided; 1..3
//       point lights above; a camera anywhere around), rendered by the
//       reference z-buffer with shadows=volume (z-pass or z-fail at random)
//       (Phong) and by the reference ray tracer at depth 1 with shadow rays, the same
//       frame without shadows from both. Unit: pixels. A pixel whose colours
//       differ by more than 1/255 is explained when the unshadowed frames
//       differ there too (`visibility`), when the oracle's answer changes
//       within 1/64 pixel (`shadow_edge`), when another surface lies within
//       1e-6 of the scene's size of the visible point (`contact`), or, for
//       z-pass only, when the hither plane's point on the view ray is in
//       shadow (`hither_in_shadow`: z-pass's textbook failure); anything else
//       is unexplained (props/raster/shadow_oracle.h).
//   ShadowVolumes.zbuffer__simd   The same cases for the simd z-buffer
//       (optimized/zbuffer_shadow_volume.cpp), judged the same way against
//       shadow rays, and, besides, every pixel must equal the reference
//       z-buffer's bit for bit (the same shared steps and stencil rule,
//       core/shadow_volume.h): any that does not is unexplained
//       (`not_reference`), whatever the rays say, unless the two rows'
//       z-buffers see another triangle in one of its samples (`visibility_tie`:
//       the simd raster's depth plane is within a few ulps of the reference's,
//       so at a near tie of two surfaces the other may win; the same pixel
//       then differs with shadows=map too; measured in deep mode: 1 pixel in
//       87213, seed 14980940616048128707).
#include <cmath>

#include "props/gen/numbers.h"
#include "props/raster/parts.h"
#include "optimized/raster.h"
#include "props/raster/shadow_oracle.h"
#include "reference/raster.h"
#include "reference/ray_trace.h"

namespace lockstep::props::raster {

namespace {

std::string vec(const Vec3& v) { return num(v.x) + " " + num(v.y) + " " + num(v.z); }

std::string tri(const Vec3& a, const Vec3& b, const Vec3& c) {
  return "p 3\n" + vec(a) + "\n" + vec(b) + "\n" + vec(c) + "\n";
}

rc::Gen<RasterCase> shadow_scene() {
  return rc::gen::exec([] {
    RasterCase c;
    c.width = *rc::gen::inRange(24, 65);
    c.height = *rc::gen::inRange(24, 65);
    const Vec3 from{*gen::uniform(-7, 7), *gen::uniform(0.5, 8), *gen::uniform(5, 12)};
    std::string s = "v\nfrom " + vec(from) + "\nat " + num(*gen::uniform(-1, 1)) + " " +
                    num(*gen::uniform(0, 1)) + " 0\nup 0 1 0\nangle " + num(*gen::uniform(30, 70)) +
                    "\nhither 0.01\nresolution " + std::to_string(c.width) + " " +
                    std::to_string(c.height) + "\nb 0.1 0.2 0.3\n";
    const int lights = *rc::gen::inRange(1, 4);
    for (int k = 0; k < lights; ++k)
      s += "l " + vec({*gen::uniform(-8, 8), *gen::uniform(4, 14), *gen::uniform(-8, 8)}) + "\n";
    s += "f 0.8 0.8 0.7 0.9 0.2 20 0 1\np 4\n-9 0 9\n9 0 9\n9 0 -9\n-9 0 -9\n";
    const int occluders = *rc::gen::inRange(1, 5);
    for (int k = 0; k < occluders; ++k) {
      s += "f " + num(*gen::uniform(0.2, 1)) + " " + num(*gen::uniform(0.2, 1)) + " " +
           num(*gen::uniform(0.2, 1)) + " 0.8 0.3 20 0 1\n";
      const Vec3 centre{*gen::uniform(-4, 4), *gen::uniform(0.3, 4), *gen::uniform(-4, 4)};
      const double size = *gen::uniform(0.3, 1.5);
      // Outward-facing triangles of a box or a tetrahedron; then maybe
      // inside out (all reversed: still consistent), one flipped, one dropped.
      std::vector<std::array<Vec3, 3>> tris;
      if (*rc::gen::inRange(0, 2) == 0) {
        const Vec3 h{size * *gen::uniform(0.3, 1), size * *gen::uniform(0.3, 1),
                     size * *gen::uniform(0.3, 1)};
        auto p = [&](int b) {
          return centre + Vec3{(b & 1) ? h.x : -h.x, (b & 2) ? h.y : -h.y, (b & 4) ? h.z : -h.z};
        };
        const int quads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                 {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
        for (const auto& q : quads) {
          tris.push_back({p(q[0]), p(q[1]), p(q[2])});
          tris.push_back({p(q[0]), p(q[2]), p(q[3])});
        }
      } else {
        Vec3 v[4];
        for (Vec3& x : v)
          x = centre +
              size * Vec3{*gen::uniform(-1, 1), *gen::uniform(-1, 1), *gen::uniform(-1, 1)};
        const int faces[4][3] = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
        const Vec3 mid = (v[0] + v[1] + v[2] + v[3]) / 4.0;
        for (const auto& f : faces) {
          std::array<Vec3, 3> t{v[f[0]], v[f[1]], v[f[2]]};
          if (dot(cross(t[1] - t[0], t[2] - t[0]), t[0] - mid) < 0) std::swap(t[1], t[2]);
          tris.push_back(t);
        }
      }
      const int variant = *rc::gen::inRange(0, 6);
      if (variant == 0)
        for (auto& t : tris) std::swap(t[1], t[2]);
      if (variant == 1) std::swap(tris[0][1], tris[0][2]);
      if (variant == 2) tris.pop_back();
      for (const auto& t : tris) s += tri(t[0], t[1], t[2]);
    }
    const int loose = *rc::gen::inRange(0, 4);
    for (int k = 0; k < loose; ++k) {
      s += "f 0.6 0.6 0.9 0.8 0.3 20 " + num(*rc::gen::element(0.0, 0.5)) + " 1\n";
      const Vec3 centre{*gen::uniform(-4, 4), *gen::uniform(0.3, 5), *gen::uniform(-4, 4)};
      auto corner = [&] {
        return centre +
               Vec3{*gen::uniform(-1.5, 1.5), *gen::uniform(-1.5, 1.5), *gen::uniform(-1.5, 1.5)};
      };
      s += tri(corner(), corner(), corner());
    }
    c.nff = s;
    c.params.set("shading", "phong");  // the ray tracer's lighting
    c.params.set("shadows", "volume");
    c.params.set("zfail", *rc::gen::element<std::string>("0", "1"));
    return c;
  });
}

// reference: when given, the image must also equal its, pixel for pixel.
Verdict shadow_case(const FamilyImpl& impl, const FamilyImpl* reference, const RasterCase& c) {
  const std::shared_ptr<const Scene> scene = c.scene();
  const Input in = make_input<Scene>(*scene, "<case>", c.width, c.height, scene->background);
  FrameOptions vo = c.options();
  const Image vol = impl.run_as<Image>(in, vo, nullptr);
  const Image same = reference ? reference->run_as<Image>(in, vo, nullptr) : Image();
  // Where the two rows' visible triangles differ (see visibility_tie above).
  std::vector<uint8_t> tie;
  if (reference) {
    const RasterSettings rs = frame_settings(*scene, vo);
    const ScreenMesh mesh = view_scene(*scene, c.width, c.height, rs);
    Visibility rv, sv;
    ref::zbuffer_visibility(mesh, rs, rv);
    opt::simd::zbuffer_visibility(mesh, rs, 1, sv);
    tie.assign(size_t(c.width) * size_t(c.height), 0);
    for (size_t k = 0; k < rv.tri.size(); ++k)
      if (rv.tri[k] != sv.tri[k]) tie[k / size_t(rv.spp)] = 1;
  }
  FrameOptions vo0 = vo;
  vo0.params = {};
  vo0.params.set("shading", "phong");
  const Image vol0 = impl.run_as<Image>(in, vo0, nullptr);
  FrameOptions ro = c.options();
  ro.params = {};
  ro.params.set("depth", "1");
  ro.params.set("shadows", "rays");
  const Image rays = ref::trace_render(*scene, ro, nullptr);
  ro.params = {};
  ro.params.set("depth", "1");
  ro.params.set("shadows", "none");
  const Image rays0 = ref::trace_render(*scene, ro, nullptr);
  const bool zfail = c.params.get("zfail") == "1";
  const Camera cam = Camera::from_view(scene->view, c.width, c.height);
  const double hither = view_frame(*scene, c.width, c.height).near_z;
  Vec3 lo, hi;
  scene_bounds(*scene, lo, hi);
  const double delta = 1e-6 * length(hi - lo);
  auto differs = [](const Image& a, const Image& b, int i, int j) {
    const float *p = a.pixel(i, j), *q = b.pixel(i, j);
    return std::max({std::abs(p[0] - q[0]), std::abs(p[1] - q[1]), std::abs(p[2] - q[2])}) >
           1.0f / 255;
  };
  Verdict v;
  auto equal = [](const Image& a, const Image& b, int i, int j) {
    const float *p = a.pixel(i, j), *q = b.pixel(i, j);
    return p[0] == q[0] && p[1] == q[1] && p[2] == q[2];
  };
  for (int j = 0; j < c.height; ++j)
    for (int i = 0; i < c.width; ++i) {
      Outcome o;
      if (reference && !equal(vol, same, i, j)) {
        o.err = 1;
        o.measured = true;
        o.kind = Outcome::unexplained;
        o.label = "not_reference";
        if (tie[size_t(j) * size_t(c.width) + size_t(i)]) {
          o.kind = Outcome::explained;
          o.label = "visibility_tie";
        }
        o.detail = "pixel (" + std::to_string(i) + ", " + std::to_string(j) +
                   "): differs from the reference z-buffer's shadow volumes (" +
                   (zfail ? "z-fail" : "z-pass") + ")";
        v.rays.push_back(o);
        continue;
      }
      if (!differs(vol, rays, i, j)) {
        v.rays.push_back(o);
        continue;
      }
      o.err = 1;
      o.measured = true;
      o.kind = Outcome::explained;
      const double px = i + 0.5, py = j + 0.5;
      if (differs(vol0, rays0, i, j)) {
        o.label = "visibility";
      } else if (shadow_oracle::near_edge(*scene, cam, px, py, shadow_oracle::kEdgeRadius)) {
        o.label = "shadow_edge";
      } else if (!zfail && shadow_oracle::hither_in_shadow(*scene, cam, px, py, hither)) {
        o.label = "hither_in_shadow";
      } else if (shadow_oracle::contact(*scene, cam, px, py, delta)) {
        o.label = "contact";
      } else {
        o.kind = Outcome::unexplained;
        o.label = "wrong";
        o.detail = "pixel (" + std::to_string(i) + ", " + std::to_string(j) + "): shadow volume (" +
                   (zfail ? "z-fail" : "z-pass") +
                   ") and shadow rays disagree away from any shadow edge";
      }
      v.rays.push_back(o);
    }
  return v;
}

}  // namespace

void shadow_volume_part(const Family& family, FamilyProperties& out) {
  const FamilyImpl* reference = family.find("reference");
  if (!reference) return;
  const FamilyImpl impl = *reference;
  out.properties.push_back(
      case_property(family, *reference, "ShadowVolumes", "shadow_scene", shadow_scene(), 0,
                    "pixels", [impl](const RasterCase& c) { return shadow_case(impl, nullptr, c); }));
  if (const FamilyImpl* simd = family.find("simd"))
    out.properties.push_back(case_property(
        family, *simd, "ShadowVolumes", "shadow_scene", shadow_scene(), 0, "pixels",
        [impl, row = *simd](const RasterCase& c) { return shadow_case(row, &impl, c); }));
}

}  // namespace lockstep::props::raster

// lockstep reference: radiosity (reference/radiosity.h).
//
// Goral, Torrance, Greenberg and Battaile, "Modeling the interaction of light
// between diffuse surfaces" (1984); Cohen and Greenberg, "The hemi-cube"
// (1985); Cohen and Wallace, "Radiosity and Realistic Image Synthesis" (1993),
// ch. 4-5. The lecture notes' steps, one by one:
//   1. cut the surfaces into patches small enough that each is one colour;
//   2. form factors: how much of the light leaving patch i reaches patch j;
//   3. solve B_i = E_i + rho_i sum_j F_ij B_j (energy conservation);
//   4. display: vertex radiosities, Gouraud-interpolated through the
//      z-buffer, with no light sources (the solution replaces ambient light).
#include "reference/radiosity.h"

#include <cmath>
#include <string>

#include "core/error.h"
#include "reference/raster.h"

namespace lockstep::ref {

// Every triangle of the scene but the two patches' own polygons, by Moller and
// Trumbore (core/radiosity.h segment_meets_triangle).
bool segment_clear(const Scene& scene, const Vec3& a, const Vec3& b, int from, int to) {
  const Vec3 d = b - a;
  for (size_t k = 0; k < scene.tri_vertex.size(); ++k) {
    const int poly = int(scene.tri_poly[k]);
    if (poly == from || poly == to) continue;
    const auto& t = scene.tri_vertex[k];
    if (segment_meets_triangle(a, d, kSegmentMargin, 1 - kSegmentMargin, scene.vertex[t[0]], scene.vertex[t[1]],
                               scene.vertex[t[2]]))
      return false;
  }
  return true;
}

FormFactors form_factors_rays(const Scene& scene, const PatchMesh& mesh, int k, FormFactorMethod method) {
  const size_t n = mesh.patches.size();
  FormFactors f(n * n, 0.0);
  for (size_t i = 0; i < n; ++i) {
    const Vec3 c = mesh.patches[i].centre();
    for (size_t j = 0; j < n; ++j) {
      // Unoccluded: Lambert's contour integral from i's centre over j, or
      // Sparrow's double contour integral over both (exact).
      const double unoccluded =
          method == FormFactorMethod::exact ? exact_form_factor(mesh, i, j) : centre_form_factor(mesh, i, j);
      if (!(unoccluded > 0)) continue;
      // Occluded: the share of rays from the centre to j's points that arrive.
      const std::vector<Vec3> targets = patch_targets(mesh.patches[j], k);
      int arrived = 0;
      for (const Vec3& y : targets)
        if (segment_clear(scene, c, y, mesh.patches[i].polygon, mesh.patches[j].polygon)) ++arrived;
      f[i * n + j] = unoccluded * arrived / double(targets.size());
    }
  }
  return f;
}

FormFactors form_factors_hemicube(const PatchMesh& mesh, int res) {
  const size_t n = mesh.patches.size();
  FormFactors f(n * n, 0.0);
  const HemicubeWeights w = hemicube_weights(res);
  const RasterSettings s = radiosity_item_buffer();
  Scene items = patch_scene(mesh, View{});
  const double near = hemicube_near(mesh);
  for (size_t i = 0; i < n; ++i) {
    const Patch& from = mesh.patches[i];
    const Vec3 c = from.centre(), normal = from.normal();
    for (int face = 0; face < 5; ++face) {
      // The face's view, through the reference z-buffer: which patch each pixel sees.
      items.view = hemicube_view(c, normal, face, res, near, hemicube_turn(size_t(i)));
      const ScreenMesh screen = view_scene(items, res, res, s);
      Visibility vis;
      zbuffer_visibility(screen, s, vis);
      // Each pixel's delta form factor to the patch it sees.
      add_hemicube_face(mesh, items, screen, vis, w, i, face, &f[i * n]);
    }
  }
  return f;
}

Image radiosity(const Scene& scene, const FrameOptions& opts, FrameStats* stats) {
  const RadiositySettings rs = radiosity_settings(opts.params, scene.source);
  // 1. Patches, 2. form factors, 3. solve (core/radiosity.h solve_scene:
  // with --error, refined where neighbours differ and solved again).
  if (opts.progress) opts.progress(0.0);
  const RadiositySolution sol = solve_scene(scene, rs, [&](const PatchMesh& mesh, FormFactors) {
    return rs.method == FormFactorMethod::hemicube ? form_factors_hemicube(mesh, rs.hemicube)
                                                   : form_factors_rays(scene, mesh, rs.rays, rs.method);
  });
  const PatchMesh& mesh = sol.mesh;
  const SolveResult& solved = sol.solved;
  if (opts.progress) opts.progress(0.8);
  // 4. Display: the patches through the z-buffer, vertex radiosities interpolated.
  const Scene items = patch_scene(mesh, scene.view);
  const RasterSettings s = radiosity_item_buffer();
  const ScreenMesh screen = view_scene(items, opts.width, opts.height, s);
  Visibility vis;
  zbuffer_visibility(screen, s, vis);
  const std::vector<Vec3> vertex_b = vertex_radiosity(mesh, solved.b);
  Image image = radiosity_image(items, mesh, vertex_b, screen, vis, scene.background);
  radiosity_sides(mesh, solved.b, vertex_b, opts, stats);
  if (stats) radiosity_notes(sol, rs, *stats);
  if (opts.progress) opts.progress(1.0);
  return image;
}

}  // namespace lockstep::ref

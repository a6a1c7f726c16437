// lockstep props/raster: the z-buffer's visibility kernel (ScreenMesh ->
// Visibility), below the viewing pipeline: screen-space triangles are generated
// directly, in snapped 1/256-pixel coordinates, so that vertices and edges land
// exactly on sample positions as often as between them.
//
//   CoverageAgreement.zbuffer_visibility__simd
//       opt::simd::zbuffer_visibility against ref::zbuffer_visibility on random
//       triangle soups (spp 1 and 4, regular and rotated grids, every depth
//       format, huge triangles whose edge functions leave int32): per sample,
//       the coverage count is identical; the visible triangle is identical
//       unless the two candidates' depths (the reference's own arithmetic) are
//       within the format's tie band (`known_simd_depth_tie`, per sample,
//       capped: kDepthTie) -- never for exact copies, which have equal depths
//       in any arithmetic: there the first drawn must win, as in the
//       reference (`tie_order`, unexplained); where the triangle is the
//       same, the stored depth is within the format's bound (depth_bound).
//   DrawOrder.zbuffer_visibility__simd
//       opt::simd::zbuffer_visibility drawing every tile in reverse (order=
//       reverse: ties win) against drawing it in mesh order (order=mesh), on the
//       same soups (exact copies at equal depth among them): triangle, count and
//       stored depth identical, bit for bit. Bound 0. Mutant reverse_strict
//       (reverse order, ties lose: the last of equal depths kept) is caught here.
//   Watertight.zbuffer_visibility__{reference,simd}
//       closed meshes that cover the whole frame -- a jittered grid with random
//       diagonals, or a fan around one vertex, with vertices at random
//       sub-pixel positions or exactly on samples -- cover every sample exactly
//       once (count == 1): no holes, no double writes (the Khronos fill-rule
//       tests' additive accumulation).
//   SetupIdentical.zbuffer__simd (random soups, half of them edge_on_soup:
//       faces seen edge-on, where the two culling tests part) and .zbuffer__simd_corpus
//       (corpus scenes x culling modes x shadings x 1-2 threads):
//       opt::simd::view_scene's mesh is view_scene's, bit for bit.
//   SimdTargets.zbuffer__simd: the same agreement on fixed soups, and corpus
//       frames against the reference, on every Highway target compiled (flat
//       shading among them: the image path's own set-up, view_sphere's
//       triangle_step, the polygons' clipping test and culling
//       (corpus/scenes/clip-tris.nff, every culling mode), polygon_run
//       (mount-3 in float and reversed depth) and set_up_forward, which no
//       visibility soup reaches), with the stats' triangle count.
//   Mutants: inclusive_edges (every edge owns its samples: caught by Watertight),
//       bottom_right (the mirror rule, watertight but not the contract:
//       caught by CoverageAgreement) and last_tie_wins (of equal depths the
//
// The case format, generators, subjects and checks: vis_case.cpp (visibility.h);
// the set-up's identity: setup_identical.cpp; every Highway target: simd_targets.cpp.
#include "props/raster/parts.h"
#include "props/raster/visibility.h"

namespace lockstep::props::raster {

using namespace vis;

void visibility_part(const Family& family, FamilyProperties& out) {
  const Subject reference{"reference", ref::zbuffer_visibility};
  const Subject simd{"simd", simd_1};
  out.properties.push_back(agreement_property(simd));
  out.properties.push_back(watertight_property(reference));
  out.properties.push_back(watertight_property(simd));
  out.properties.push_back(draw_order_property(simd));
  // A later copy winning equal depths (what `>=` for `>` in the reversed
  // depth test did): CoverageAgreement's tie_order must catch it.
  out.mutants.push_back({"last_tie_wins",
                         "of equal depths the last drawn kept (a strict test in reverse order)",
                         "coverage_agreement",
                         {agreement_property({"last_tie_wins", reverse_strict})}});
  out.mutants.push_back({"reverse_strict",
                         "tiles drawn in reverse with a strict depth test (the last of equal "
                         "depths kept)",
                         "draw_order",
                         {draw_order_property({"reverse_strict", reverse_strict})}});
  const Subject inclusive{"inclusive_edges", broken<0>};
  const Subject bottom_right{"bottom_right", broken<1>};
  out.mutants.push_back({"inclusive_edges",
                         "samples on an edge belong to both triangles",
                         "watertight",
                         {agreement_property(inclusive), watertight_property(inclusive)}});
  out.mutants.push_back({"bottom_right",
                         "the mirror fill rule (bottom and right edges own their samples)",
                         "coverage_agreement",
                         {agreement_property(bottom_right), watertight_property(bottom_right)}});
  out.fixed.push_back({"SimdTargets", "zbuffer__simd", [&family] { every_target(family); }});
  out.fixed.push_back({"FlatShine", "zbuffer__simd", [&family] { flat_shine(family); }});
  // The optimized set-up (opt::simd::view_scene) makes view_scene's mesh.
  out.fixed.push_back({"SetupIdentical", "zbuffer__simd_corpus", setup_identical});
  if (const FamilyImpl* simd = family.find("simd")) {
    // Half the soups nearly edge-on: where world- and projection-space
    // culling part, the set-up must part exactly as view_scene does.
    Property p = case_property(family, *simd, "SetupIdentical", "edge_on_or_soup",
                               rc::gen::oneOf(edge_on_soup(), triangle_soup()), 0, "meshes differing",
                               setup_case);
    p.units = "set-ups (culling mode x shading)";
    out.properties.push_back(std::move(p));
  }
}

}  // namespace lockstep::props::raster

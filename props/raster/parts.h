// lockstep props/raster: the parts of the raster families' properties.
//
// Each part adds what it tests of the family it is given to out; it runs for
// the families whose row names it (Family::properties, registry/raster_rows.cpp);
// properties.cpp lists them by name. A new part: its file in props/raster/,
// its declaration here, its line in kParts (properties.cpp), its name in the
// rows it applies to, its file in props/CMakeLists.txt.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "props/property.h"
#include "props/raster/exact_coverage.h"
#include "props/raster/raster_case.h"
#include "reference/raster.h"

namespace lockstep::props::raster {

// A property over RasterCases of one implementation: check judges one case
// (its Outcomes are pixels or samples); the counterexample text is the case.
// suite "RayCastCrossCheck" gives check "ray_cast_cross_check" and the test
// RayCastCrossCheck.<family>__<impl>.
Property case_property(const Family& family, const FamilyImpl& impl, std::string suite,
                       std::string generator, rc::Gen<RasterCase> gen, double bound,
                       std::string unit, std::function<Verdict(const RasterCase&)> check);

// z-buffer frames against ray casting (properties.cpp).
void cross_check_part(const Family& family, FamilyProperties& out);
// Supersampling against the exact box-filtered image (supersampling.cpp).
void supersampling_part(const Family& family, FamilyProperties& out);
// Its scenes: 1..5 flat, two-sided triangles parallel to the image plane at
// distinct depths; and their screen triangles for the exact oracle.
rc::Gen<RasterCase> flat_parallel_scene();
std::vector<FlatTri> flat_tris(const Scene& scene, const ScreenMesh& mesh);
// An implementation's frame against the reference's, pixel for pixel: coverage
// identical, colour within color_abs; another triangle visible where two
// candidates' depths tie is labelled with tie's label (its rate capped by the
// driver when the property's known failure is tie), a pixel near a spot
// cone's edge `spot_edge`; a coverage difference is the implementation's
// known failure if that is `coverage` (render_agree.cpp).
Verdict image_agree(const FamilyImpl& impl, const FamilyImpl& reference, const RasterCase& c, double color_abs,
                    const KnownFailure& tie);
// RenderAgree: image_agree on shaded_soup scenes (render_agree.cpp).
void render_agree_part(const Family& family, FamilyProperties& out);
// World-space against projection-space back-face culling (culling.cpp).
void culling_part(const Family& family, FamilyProperties& out);
// scanline: coverage against the z-buffer on snapped meshes, frames against the z-buffer
// (scanline.cpp).
void scanline_part(const Family& family, FamilyProperties& out);
// scanline: the interpolation lessons, measured (interpolation.cpp).
void interpolation_part(const Family& family, FamilyProperties& out);
// The z-buffer's visibility kernel: coverage agreement, watertightness, fill-rule
// mutants; the optimized set-up's mesh against view_scene's (visibility.cpp).
void visibility_part(const Family& family, FamilyProperties& out);
// The llvmpipe peer's coverage against the reference's (llvmpipe.cpp).
void llvmpipe_part(const Family& family, FamilyProperties& out);
// The simd z-buffer's hidden-sphere skipping changes no bit of the image (hidden.cpp).
void hidden_part(const Family& family, FamilyProperties& out);
// The painter against the z-buffer, its reports, --split, its exact predicates (painter.cpp).
void painter_part(const Family& family, FamilyProperties& out);
// The painter's failure map (painter.cpp): random 64x64 flat scenes of one kind
// ("cyclic_triple" or "interpenetrating_pair") drawn by impl without and with
// split, each against the z-buffer.
struct PainterMapCase {
  std::string nff;
  double wrong_fraction = 0;  // wrong pixels over the pixels the scene covers
  int wrong = 0;              // pixels whose coverage or colour differs from the z-buffer's
  bool reported = false;      // the painter reported a cycle or an interpenetration
  int wrong_split = 0;        // wrong pixels with split=1
};
std::vector<PainterMapCase> painter_failure_map(const FamilyImpl& impl, const std::string& kind,
                                                int cases, uint64_t seed);

// The z-buffer's two shadow settings, parts of its properties:
// shadows=volume against shadow rays on random triangle scenes (shadow_volume.cpp);
void shadow_volume_part(const Family& family, FamilyProperties& out);
// shadows=map: cube faces, texels, no occluder = no shadow, agreement with shadow
// rays (shadow_map.cpp).
void shadow_map_part(const Family& family, FamilyProperties& out);

// Coplanar duplicates: the first drawn wins every tie, every row, every depth
// format and draw order (first_drawn.cpp).
void first_drawn_part(const Family& family, FamilyProperties& out);

}  // namespace lockstep::props::raster

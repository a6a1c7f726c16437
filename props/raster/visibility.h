// lockstep props/raster: the z-buffer visibility kernel's cases, subjects and
// checks (vis_case.cpp), shared by visibility.cpp (which registers them),
// setup_identical.cpp and simd_targets.cpp. See visibility.cpp for the
// properties.
#pragma once

#include <rapidcheck.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/family.h"
#include "props/property.h"
#include "props/raster/raster_case.h"
#include "reference/raster.h"

namespace lockstep::props::raster::vis {

// A case: screen-space triangles in snapped 1/256-pixel coordinates.
struct VisCase {
  int width = 16, height = 16;
  int spp = 1;
  SampleGrid grid = SampleGrid::kRegular;
  DepthFormat depth = DepthFormat::kFloat;
  struct Vertex {
    int32_t x, y;
    double z;
  };
  std::vector<std::array<Vertex, 3>> tris;  // any orientation; zero area is dropped
};

using VisFn = void (*)(const ScreenMesh&, const RasterSettings&, Visibility&);

struct Subject {
  std::string name;
  VisFn fn;
};

// The stored depth of mesh triangle t at sample (px, py) (1/256 px), as the
// reference computes it (perspective-correct: affine in 1/z on screen).
double ref_depth(const ScreenMesh& m, const RasterSettings& s, uint32_t t, int64_t px, int64_t py);

// opt::simd::zbuffer_visibility on one thread.
void simd_1(const ScreenMesh& m, const RasterSettings& s, Visibility& v);
// Mutant: drawn in reverse with a strict depth test (the last of equal depths kept).
void reverse_strict(const ScreenMesh& m, const RasterSettings& s, Visibility& v);
// Mutants: the reference's loop with another ownership rule for samples on an
// edge: 0 inclusive (every edge owns them), 1 bottom-right (the mirror of top-left).
template <int kRule>
void broken(const ScreenMesh& mesh, const RasterSettings& s, Visibility& vis);

// The checks (one Outcome per sample).
Verdict agreement(const Subject& subj, const VisCase& c);
Verdict draw_order(const Subject& subj, const VisCase& c);
Verdict watertight(const Subject& subj, const VisCase& c);

// Their properties (CoverageAgreement, DrawOrder, Watertight) for a subject.
Property agreement_property(const Subject& s);
Property draw_order_property(const Subject& s);
Property watertight_property(const Subject& s);

// The optimized set-up against view_scene (setup_identical.cpp): on corpus
// scenes (a fixed test), and on one RasterCase (every culling mode x shading).
void setup_identical();
Verdict setup_case(const RasterCase& c);

// Every compiled Highway target (simd_targets.cpp).
void every_target(const Family& family);
void flat_shine(const Family& family);

}  // namespace lockstep::props::raster::vis

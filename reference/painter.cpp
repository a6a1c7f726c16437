// lockstep reference: the painter's algorithm (reference/painter.h).
//
// Method (Newell, Newell and Sancha 1972; Foley et al., 2nd ed., 15.5.1):
//   1. Depth sort: every triangle by its farthest eye depth, back to front.
//   2. For each pair whose screen extents overlap, decide whether it needs an
//      order, and which, with the NNS tests in their textbook order
//      (classify_pair). Each answer "p must be drawn before q" is an edge of the
//      must-draw-before graph. NNS splits a polygon when every test fails; we
//      instead find out exactly what the pair is: interpenetrating (an exact
//      triangle-triangle intersection test) or in a definite order (the depth
//      difference at one point of their common screen area).
//   3. The strongly connected components of that graph (Tarjan 1972): a
//      component with more than one triangle is a cycle, which no order draws
//      right. Interpenetrating pairs join their two triangles' components.
//   4. Draw the components in a topological order of the component graph
//      (Kahn 1962), the earliest in the depth sort first; inside a component the
//      triangles go in depth-sort order -- or, with settings.split, each sample
//      goes to the component's triangle in front at that sample: the component
//      split along its triangles' planes as finely as the samples can see.
//   Every triangle fills its samples with the z-buffer's fill rule, sample
//   positions and shade_fragment, so that a right order gives the z-buffer's
//   image, sample for sample.
#include "reference/painter.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"

namespace lockstep {

// ---------------------------------------------------------------- the frame

namespace ref {

Image painter(const Scene& scene, const FrameOptions& opts, FrameStats* stats) {
  const RasterSettings s = frame_settings(scene, opts);
  const int w = opts.width, h = opts.height;
  const double samples = double(w) * h * s.spp;
  const ScreenMesh mesh = view_scene(scene, w, h, s);
  const auto offsets = sample_offsets(s);
  const int spp = int(offsets.size());

  // Steps 1-3: the triangles as the painter sees them, sorted and ordered.
  std::vector<PainterTri> tris;
  tris.reserve(mesh.tris.size());
  for (const ScreenTri& t : mesh.tris) tris.push_back(painter_tri(t));
  const PainterPlan plan = painter_plan(tris);

  // Step 4: paint. Per sample: its colour and eye depth (stored as the z-buffer
  // stores them), and the triangle painted last.
  std::vector<Vec3f> color(size_t(samples), Vec3f(scene.background));
  std::vector<float> depth(color.size(), float(kInfinity));
  std::vector<uint32_t> owner(color.size(), Visibility::kNone);
  for (size_t n = 0; n < plan.order.size(); ++n) {
    if (opts.progress && (n & 4095) == 0) opts.progress(double(n) / double(plan.order.size()));
    const uint32_t t = plan.order[n];
    const PainterTri& pt = tris[t];
    const bool resolve = s.split && plan.group_size[plan.group[t]] > 1;
    // The pixels whose samples can lie inside the triangle's extent.
    const int64_t i0 = std::max<int64_t>(0, floor_div(pt.xmin, kSubpixel));
    const int64_t i1 = std::min<int64_t>(w - 1, floor_div(pt.xmax, kSubpixel));
    const int64_t j0 = std::max<int64_t>(0, floor_div(pt.ymin, kSubpixel));
    const int64_t j1 = std::min<int64_t>(h - 1, floor_div(pt.ymax, kSubpixel));
    for (int64_t j = j0; j <= j1; ++j) {
      for (int64_t i = i0; i <= i1; ++i) {
        for (int k = 0; k < spp; ++k) {
          const int64_t sx = i * kSubpixel + offsets[k][0];
          const int64_t sy = j * kSubpixel + offsets[k][1];
          // Edge functions, e[v] opposite vertex v; coverage by the fill rule.
          std::array<int64_t, 3> e;
          for (int v = 0; v < 3; ++v) {
            const int a = (v + 1) % 3, b = (v + 2) % 3;
            e[v] = edge_function(pt.x[a], pt.y[a], pt.x[b], pt.y[b], sx, sy);
          }
          if (!painter_covers(mesh.tris[t], e)) continue;
          const size_t idx = (size_t(j) * size_t(w) + size_t(i)) * size_t(spp) + size_t(k);
          // Split: inside a cycle or interpenetration, the sample goes to the
          // group's triangle in front there (exactly; ties to the first, as the z-buffer).
          if (resolve && owner[idx] != Visibility::kNone &&
              plan.group[owner[idx]] == plan.group[t] &&
              !nearer_at(pt, t, tris[owner[idx]], owner[idx], sx, sy))
            continue;
          const Fragment f = painter_fragment(mesh, t, sx, sy, e, pt.area, s.perspective);
          color[idx] = Vec3f(shade_fragment(scene, mesh, s, f));
          depth[idx] = float(f.z);
          owner[idx] = t;
        }
      }
    }
  }

  // Resolve: the box filter over each pixel's samples; depth is the nearest sample's.
  Image image(w, h);
  image.depth.assign(size_t(w) * size_t(h), float(kInfinity));
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      Vec3 sum;
      float z = float(kInfinity);
      for (int k = 0; k < spp; ++k) {
        const size_t idx = (size_t(j) * size_t(w) + size_t(i)) * size_t(spp) + size_t(k);
        sum += Vec3(color[idx]);
        z = std::min(z, depth[idx]);
      }
      image.set(i, j, sum / double(spp));
      image.depth[size_t(j) * size_t(w) + size_t(i)] = z;
    }
  }
  if (stats) {
    stats->items = mesh.scene_tris + mesh.sphere_tris;
    stats->dropped = mesh.dropped;
    stats->notes = painter_notes(mesh, plan, s.split);
  }
  if (opts.progress) opts.progress(1.0);
  return image;
}

}  // namespace ref
}  // namespace lockstep

// lockstep_volume_study: the volume families' measurements for BENCHMARKS.md
// (issue #20). Each study prints CSV on stdout and checks the claims
// BENCHMARKS.md makes of it (exit 1 and a message on stderr when one does not
// hold), so the ctest volume_study.quick keeps the claims true;
// bench/scripts/volume_charts.py draws the charts from the full runs.
//
//   step   speed against accuracy of volume ray casting: every implementation
//          of the `volume` family (reference, simd, volpack where built) at
//          steps 2 .. 1/8 voxel (a peer: its one point), on 1 and 2 threads,
//          against a very fine step (1/16, the same eps): mean and
//          largest error per channel, and time per frame (the second of two
//          runs). Full: the CT head (bone, skin) and the MRI at 512^2 (the
//          reference down to step 1/2); quick: the buckyball and
//          Marschner-Lobb at 64^2.
//   cross  the check no single tool has: the marching-cubes mesh of a field,
//          drawn by the z-buffer, against the isosurface of the same field
//          ray cast (volume_iso), same view, for grids n = 12 .. 96 (sphere,
//          torus): pixels covered by one and not the other (silhouette pixels)
//          and the depth difference where both cover, converging as h shrinks.
//          The z-buffer has no parallel projection: its camera stands 1000
//          bounding radii away with the matching narrow field of view, which
//          moves a point at most 1/1000 of its distance from the image centre
//          (0.13 pixel at the edge of a 256 pixel frame).
//
// usage: lockstep_volume_study step|cross|all [--quick]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include "bench/studies/study.h"
#include "core/camera.h"
#include "core/mesh.h"
#include "core/scene.h"
#include "io/volume_io.h"
#include "core/volume_render.h"
#include "io/volume_settings.h"
#include "registry/loaders.h"
#include "registry/registry.h"

namespace lockstep {
namespace {

struct Options {
  bool quick = false;
  study::Claims claims{"lockstep_volume_study"};
};

double seconds_of(const std::function<void()>& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

Params params_of(std::initializer_list<std::pair<const char*, std::string>> kv) {
  Params p;
  for (const auto& [k, v] : kv) p.set(k, v);
  return p;
}

Image render(const Family& f, const FamilyImpl& impl, const Input& in, int size, const Params& p, double* secs,
             int threads = 1) {
  FrameOptions o;
  o.width = o.height = size;
  o.threads = threads;
  o.params = p;
  Image img;
  const double s = seconds_of([&] { img = take_output<Image>(impl.run(in, o, nullptr)); });
  if (secs) *secs = s;
  return img;
}

// ---------------------------------------------------------------- step

struct StepInput {
  std::string name, path, tf, view;
};

void step_study(Options& o) {
  const Family& f = *registry().find("volume");
  std::vector<StepInput> inputs;
  int size = 512;
  if (o.quick) {
    size = 64;
    inputs = {{"bucky", std::string(LOCKSTEP_CORPUS_DIR) + "/volumes/bucky.nhdr",
               std::string(LOCKSTEP_CORPUS_DIR) + "/tf/bucky.tf", "30,20"},
              {"ml-41", std::string(LOCKSTEP_CORPUS_DIR) + "/volumes/ml-41.field",
               std::string(LOCKSTEP_CORPUS_DIR) + "/tf/ml.tf", "0,35"}};
  } else {
    const std::string v = volumes_dir();
    inputs = {{"cthead/bone", v + "/cthead.nhdr", "ct-bone", "-90,-15,180"},
              {"cthead/skin", v + "/cthead.nhdr", "ct-skin", "-90,-15,180"},
              {"ch2/mri", v + "/ch2.nhdr", "mri", "-90,-15,180"}};
  }
  // The truth: step 1/16 with the frames' own early termination (eps 1/256:
  // a ray's error from stopping is the same order at every step, and would
  // otherwise be all a fine step shows), drawn by the fastest row
  // that must agree with the reference within the family's tolerance (simd:
  // Agreement holds it to the reference; the reference itself would take
  // minutes per 512^2 frame at that step).
  const FamilyImpl* truth_impl = &f.reference();
  for (const FamilyImpl& impl : f.impls)
    if (impl.name == "simd") truth_impl = &impl;
  std::printf("study,input,impl,threads,step,ms,mean_error,max_error\n");
  for (const StepInput& in : inputs) {
    if (!std::filesystem::exists(in.path)) continue;
    const Input input = load_volume(in.path, size, size);
    const Image fine =
        render(f, *truth_impl, input, size,
               params_of({{"tf", in.tf}, {"view", in.view}, {"step", "0.0625"}}), nullptr, 0);
    for (const FamilyImpl& impl : f.impls) {
      for (const int threads : {1, 2}) {
        if (threads == 2 && !impl.threaded) continue;
        double first_err = -1, last_err = -1;
        for (const double step : {2.0, 1.0, 0.5, 0.25, 0.125}) {
          // The reference at 512^2 only down to step 1/2 (seconds per frame beyond).
          if (!o.quick && !impl.threaded && impl.peer.empty() && step < 0.5) continue;
          const Params p = params_of({{"tf", in.tf}, {"view", in.view}, {"step", std::to_string(step)}});
          double secs = 0;
          (void)render(f, impl, input, size, p, &secs, threads);  // a first run: pages, arenas, caches
          const Image img = render(f, impl, input, size, p, &secs, threads);
          double sum = 0, worst = 0;
          for (size_t i = 0; i < img.rgba.size(); ++i) {
            const double d = std::abs(double(img.rgba[i]) - fine.rgba[i]);
            sum += d;
            worst = std::max(worst, d);
          }
          const double mean = sum / double(img.rgba.size());
          if (first_err < 0) first_err = mean;
          last_err = mean;
          std::printf("step,%s,%s,%d,%g,%.3f,%.6g,%.6g\n", in.name.c_str(), std::string(impl.name).c_str(), threads,
                      step, 1e3 * secs, mean, worst);
          std::fflush(stdout);
          if (!impl.peer.empty()) break;  // a peer's own sampling ignores the step: one point
        }
        // Ray casting converges at first order in dt: 16 times smaller a step,
        // at least 4 times smaller an error (the early-termination eps and float
        // rounding put a floor under it). Peers and shortened runs are exempt.
        if (impl.peer.empty() && (o.quick || impl.threaded))
          o.claims.check(last_err < first_err / 4,
                in.name + " " + std::string(impl.name) + ": error at step 1/8 (" + std::to_string(last_err) +
                    ") not 4x below step 2's (" + std::to_string(first_err) + ")");
      }
    }
  }
}

// ---------------------------------------------------------------- cross

// The mesh as a scene for the z-buffer: one white material, no normals (flat),
// two-sided (a transmitting material: NFF polygons are one-sided otherwise),
// seen along the volume view's direction from 1000 bounding radii.
Scene far_scene(const Mesh& m, const vr::View& view, double radius, int size) {
  Scene s;
  Material mat;
  mat.transmittance = 1e-9;
  const uint32_t id = add_material(s, mat);
  for (const auto& t : m.triangles) {
    const Vec3 p[3] = {Vec3(m.vertices[t[0]]), Vec3(m.vertices[t[1]]), Vec3(m.vertices[t[2]])};
    add_polygon(s, p, {}, id);
  }
  const double distance = 1000 * radius;
  const Vec3 centre = 0.5 * (view.lo + view.hi);
  s.view.from = centre - distance * view.dir;
  s.view.at = centre;
  s.view.up = -1.0 * normalize(view.dv);
  // The frame spans the view's at the centre plane; NFF's angle spans the edge
  // pixels' centres (core/camera.h), size - 1 pixels.
  const double half = 0.5 * (size - 1) * length(view.du);
  s.view.angle = 2 * std::atan(half / distance) * 180 / std::numbers::pi;
  s.view.hither = distance - 2 * radius;
  s.view.xres = s.view.yres = size;
  s.background = Vec3{0, 0, 0};
  s.source = "<cross mesh>";
  return s;
}

void cross_study(Options& o) {
  const Family& mc = *registry().find("marching_cubes");
  const Family& iso = *registry().find("volume_iso");
  const Family& zb = *registry().find("zbuffer");
  const int size = o.quick ? 128 : 256;
  const std::vector<int> grids = o.quick ? std::vector<int>{12, 24, 48} : std::vector<int>{12, 24, 48, 96};
  std::printf("study,field,n,h,triangles,silhouette_px,mismatch_px,mean_depth_diff,max_depth_diff\n");
  for (const FieldKind kind : {FieldKind::kSphere, FieldKind::kTorus}) {
    int first = -1, last = -1;
    double first_depth = -1, last_depth = -1;
    for (const int n : grids) {
      FieldSpec spec = field_defaults(kind);
      spec.n = n;
      const double level = natural_iso(spec);
      const Volume vol = sample_field(spec, field_name(kind));
      const Params p = params_of({{"iso", std::to_string(level)}, {"view", "20,30"}, {"step", "0.125"}});
      // The ray-cast isosurface.
      const Input vin = make_input<Volume>(Volume(vol), field_name(kind), size, size);
      const Image ray = render(iso, iso.reference(), vin, size, p, nullptr);
      // The marching-cubes mesh through the z-buffer.
      FrameOptions mo;
      mo.params = params_of({{"iso", std::to_string(level)}});
      const FamilyImpl& fast = *std::find_if(mc.impls.begin(), mc.impls.end(),
                                             [](const FamilyImpl& i) { return i.name == "simd"; });
      const Mesh mesh = take_output<Mesh>(fast.run(vin, mo, nullptr));
      const vr::View view = vr::make_view(vol, vr::settings(p, "cross", vr::Mode::kIso), size, size);
      const double radius = 0.5 * length(view.hi - view.lo);
      const Scene scene = far_scene(mesh, view, radius, size);
      const Input zin = make_input<Scene>(Scene(scene), "<cross mesh>", size, size, Vec3{0, 0, 0});
      FrameOptions zo;
      zo.width = zo.height = size;
      zo.params = params_of({{"shading", "flat"}, {"cull", "none"}});
      const Image zimg = take_output<Image>(zb.reference().run(zin, zo, nullptr));
      // Compare coverage (the ray-cast image's), and depth where both cover.
      const Camera cam = Camera::from_view(scene.view, size, size);
      int mismatch = 0, both = 0;
      double sum = 0, worst = 0;
      for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
          const bool r = ray.pixel(x, y)[3] > 0;
          const float z = zimg.depth[size_t(y) * size_t(size) + size_t(x)];
          const bool m = std::isfinite(z);
          if (r != m) {
            ++mismatch;
            continue;
          }
          if (!r) continue;
          // The interpolant's first crossing along the z-buffer's own (perspective)
          // ray through this pixel, found as the reference finds it (samples every
          // dt, then bisection): the two depths then differ by the surfaces'
          // distance alone, not by the projections'.
          const Ray pr = cam.primary(x, y);
          const double z_len = 1.0 / dot(pr.d, cam.forward);  // unit-ray length per unit of eye depth
          double t_hit = -1;
          const double t_start = 1000 * radius - 1.001 * radius;
          const long steps = long(std::ceil(2.002 * radius / view.dt));
          auto above = [&](double t) { return vr::trilinear(vol, pr.o + t * pr.d) >= level; };
          for (long k = 1; k <= steps && t_hit < 0; ++k) {
            double lo = t_start + double(k - 1) * view.dt, hi = t_start + double(k) * view.dt;
            const bool a = above(lo);
            if (a == above(hi)) continue;
            for (int b = 0; b < 40; ++b) {
              const double mid = 0.5 * (lo + hi);
              (above(mid) == a ? lo : hi) = mid;
            }
            t_hit = 0.5 * (lo + hi);
          }
          if (t_hit < 0) continue;
          const double d = std::abs(double(z) * z_len - t_hit);
          ++both;
          sum += d;
          worst = std::max(worst, d);
        }
      const double h = (spec.hi - spec.lo) / (n - 1);
      const double pixel = length(view.du);
      // The true surface's outline in pixels: the sphere's circle, the torus' two
      // outlines (an estimate; the column only scales the mismatch).
      const double outline = kind == FieldKind::kSphere ? 2 * std::numbers::pi * spec.a / pixel
                                                        : 2 * 2 * std::numbers::pi * (spec.a + spec.b) / pixel;
      const double mean = both ? sum / both : 0;
      std::printf("cross,%s,%d,%.5g,%zu,%.0f,%d,%.4g,%.4g\n", field_name(kind), n, h, mesh.triangles.size(), outline,
                  mismatch, mean, worst);
      std::fflush(stdout);
      if (first < 0) {
        first = mismatch;
        first_depth = mean;
      }
      last = mismatch;
      last_depth = mean;
    }
    const std::string name = field_name(kind);
    // Both approximate the trilinear interpolant's surface, whose distance to
    // the mesh shrinks like h^2: 8 (quick: 4) times finer a grid, the depth
    // difference at least 8 times smaller, and fewer silhouette pixels differ.
    o.claims.check(last_depth < first_depth / 8,
          name + ": mean depth difference " + std::to_string(last_depth) + " not 8x below " + std::to_string(first_depth));
    o.claims.check(last < first, name + ": silhouette mismatches did not fall (" + std::to_string(first) + " -> " +
                               std::to_string(last) + ")");
  }
}

}  // namespace
}  // namespace lockstep

int main(int argc, char** argv) {
  lockstep::Options o;
  std::string study = argc > 1 ? argv[1] : "all";
  for (int i = 2; i < argc; ++i)
    if (std::strcmp(argv[i], "--quick") == 0) o.quick = true;
  if (study != "step" && study != "cross" && study != "all") {
    std::fprintf(stderr, "usage: lockstep_volume_study step|cross|all [--quick]\n");
    return 2;
  }
  if (study == "step" || study == "all") lockstep::step_study(o);
  if (study == "cross" || study == "all") lockstep::cross_study(o);
  return o.claims.exit_code();
}

// lockstep_raster_study: the raster families' measurements for BENCHMARKS.md --
// the speed-against-accuracy curves and the failure maps of issue #7. Each
// study prints CSV on stdout and checks the claims BENCHMARKS.md makes of it
// (exit 1 and a message on stderr when one does not hold), so the ctest
// raster_study.quick keeps the claims true; bench/scripts/raster_charts.py draws
// the charts from the full runs.
//
//   tessellation   sphere scenes, z-buffer (Phong per sample) against ray casting,
//                  for sphere tessellation error targets 8 .. 1/8 pixel: triangles,
//                  time per frame, mean error and share of pixels over 1/255
//   supersampling  flat triangles against the exact box-filtered image
//                  (exact_coverage.h), spp 1 .. 256, regular and rotated grids:
//                  mean and max error, time per frame
//   zfight         two parallel planes a relative distance sep apart: the share of
//                  pixels where the back one wins, per depth format, near/far and sep
//   gouraud        a shiny sphere: Gouraud against Phong, the highlight Gouraud
//                  misses, per tessellation
//   painter        random cyclic triples and interpenetrating pairs (64x64, flat):
//                  the painter's wrong pixels against the z-buffer, whether it
//                  reported why, and the wrong pixels left with split
//
// usage: lockstep_raster_study STUDY|all [--quick] [--impl NAME]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>

#include "bench/studies/study.h"
#include "kinds/image_metrics.h"
#include "io/nff.h"
#include "core/timer.h"
#include "registry/registry.h"
#include "props/raster/exact_coverage.h"
#include "props/raster/parts.h"
#include "reference/raster.h"

namespace lockstep::props::raster {

namespace {

using study::best_time;
using study::scene_input;

struct Options {
  bool quick = false;
  std::string
      impl;  // the z-buffer implementation timed (default: simd if registered, else reference)
  study::Claims claims{"lockstep_raster_study"};
};

std::string corpus(const std::string& name) {
  return std::string(LOCKSTEP_CORPUS_DIR) + "/scenes/" + name;
}

const Family& zbuffer() { return *registry().find("zbuffer"); }
const FamilyImpl& timed_impl(const Options& o) {
  const Family& f = zbuffer();
  if (!o.impl.empty()) {
    if (const FamilyImpl* i = f.find(o.impl)) return *i;
    std::fprintf(stderr, "lockstep_raster_study: no zbuffer implementation '%s'\n", o.impl.c_str());
    std::exit(2);
  }
  if (const FamilyImpl* i = f.find("simd")) return *i;
  return f.reference();
}

// ---------------------------------------------------------------- tessellation

void tessellation(Options& o) {
  const FamilyImpl& impl = timed_impl(o);
  const FamilyImpl& caster = registry().find("ray_cast")->reference();
  const int size = o.quick ? 128 : 512;
  std::printf(
      "# tessellation: scene,tess_error,triangles,ms,mean_error,pct_over_1_255,max_error (impl %s, "
      "%dx%d)\n",
      std::string(impl.name).c_str(), size, size);
  for (const char* name : {"balls-3.nff", "shells-1.nff"}) {
    const Input in = scene_input(read_nff(corpus(name)), name);
    FrameOptions fo;
    fo.width = fo.height = size;
    fo.threads = 0;
    FrameStats st;
    const Image truth = caster.run_as<Image>(in, fo, &st);
    uint64_t last_tris = 0;
    double first_pct = -1, last_pct = 0;
    for (double e : {8.0, 4.0, 2.0, 1.0, 0.5, 0.25, 0.125}) {
      FrameOptions zo = fo;
      zo.params.set("shading", "phong");
      zo.params.set("tess_error", std::to_string(e));
      const ScreenMesh mesh =
          view_scene(input_as<Scene>(in), size, size, raster_settings(zo.params, name));
      Image img;
      const double t = best_time(o.quick ? 1 : 3, [&] { img = impl.run_as<Image>(in, zo, &st); });
      const ImageError err = compare_images(img, truth);
      std::printf("%s,%g,%llu,%.3f,%.6f,%.4f,%.4f\n", name, e, (unsigned long long)mesh.sphere_tris,
                  1e3 * t, err.mean_error, err.percent_failed(), err.max_error);
      o.claims.check(mesh.sphere_tris >= last_tris,
            std::string(name) + ": a finer tess_error never gives fewer triangles");
      last_tris = mesh.sphere_tris;
      if (first_pct < 0) first_pct = err.percent_failed();
      last_pct = err.percent_failed();
    }
    o.claims.check(last_pct < first_pct / 2,
          std::string(name) +
              ": tess_error 1/8 differs from ray casting on under half the "
              "pixels tess_error 8 does");
  }
}

// ---------------------------------------------------------------- supersampling

// Eight flat triangles parallel to the image plane (fixed seed), some thin.
Scene flat_scene(int size) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.2, 1.2), c(0, 1);
  std::string s = "v\nfrom 0 0 0\nat 0 0 -1\nup 0 1 0\nangle 40\nhither 1\nresolution " +
                  std::to_string(size) + " " + std::to_string(size) + "\nb 0.1 0.2 0.3\nl 0 0 10\n";
  const double half = std::tan(20.0 * M_PI / 180.0);
  char buf[200];
  for (int t = 0; t < 8; ++t) {
    const double z = 2 + t;
    std::snprintf(buf, sizeof buf, "f %.17g %.17g %.17g 1 0 1 0.5 1\np 3\n", c(rng), c(rng),
                  c(rng));
    s += buf;
    for (int k = 0; k < 3; ++k) {
      std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g\n", u(rng) * half * z, u(rng) * half * z,
                    -z);
      s += buf;
    }
  }
  return parse_nff(s, "<flat scene>");
}

void supersampling(Options& o) {
  const FamilyImpl& impl = timed_impl(o);
  const int size = o.quick ? 24 : 64;
  Scene scene = flat_scene(size);
  RasterSettings flat;
  flat.shading = Shading::kFlat;
  const ScreenMesh mesh = view_scene(scene, size, size, flat);
  const Image exact = exact_box_filtered(flat_tris(scene, mesh), size, size, scene.background);
  const Input in = scene_input(std::move(scene), "flat");
  std::printf(
      "# supersampling: grid,spp,ms,mean_error,max_error (impl %s, %dx%d, exact box filter)\n",
      std::string(impl.name).c_str(), size, size);
  for (const char* grid : {"regular", "rotated"}) {
    double first = -1, last = 0;
    for (int n : {1, 2, 3, 4, 8, 16}) {
      if (o.quick && n > 8) break;
      FrameOptions fo;
      fo.width = fo.height = size;
      fo.params.set("shading", "flat");
      fo.params.set("spp", std::to_string(n * n));
      fo.params.set("grid", grid);
      FrameStats st;
      Image img;
      const double t = best_time(o.quick ? 1 : 3, [&] { img = impl.run_as<Image>(in, fo, &st); });
      CompareOptions co;
      const ImageError err = compare_images(img, exact, co);
      std::printf("%s,%d,%.3f,%.6f,%.6f\n", grid, n * n, 1e3 * t, err.mean_error, err.max_error);
      if (first < 0) first = err.mean_error;
      last = err.mean_error;
    }
    o.claims.check(last < first / 5,
          std::string(grid) + ": the largest spp has a fifth of spp 1's mean error or less");
  }
}

// ---------------------------------------------------------------- z-fighting

// Two parallel planes, tilted away from the viewer so that their depth spans
// [10, 100] across the image; the red one is drawn second and is in front by a
// relative distance sep. A pixel is wrong where the green (back) one shows.
double wrong_fraction(DepthFormat format, double near_z, double sep, int size) {
  char buf[600];
  std::string s;
  std::snprintf(buf, sizeof buf,
                "v\nfrom 0 0 0\nat 0 0 -1\nup 0 1 0\nangle 40\nhither %.17g\nresolution %d %d\nb 0 "
                "0 0\nl 0 10 0\n",
                near_z, size, size);
  s += buf;
  const double b =
      1 + sep;  // the back plane: the front one's points scaled by 1 + sep from the eye
  for (int k = 0; k < 2; ++k) {
    const double m = k == 0 ? b : 1;
    std::snprintf(buf, sizeof buf,
                  "f %d %d 0 1 0 1 0 1\np 4\n%.17g %.17g %.17g\n%.17g %.17g %.17g\n%.17g %.17g "
                  "%.17g\n%.17g %.17g %.17g\n",
                  k, 1 - k, -60 * m, -60 * m, -100 * m, 60 * m, -60 * m, -100 * m, 6 * m, 6 * m,
                  -10 * m, -6 * m, 6 * m, -10 * m);
    s += buf;
  }
  const Scene scene = parse_nff(s, "<zfight>");
  RasterSettings rs;
  rs.shading = Shading::kFlat;
  rs.depth = format;
  const ScreenMesh mesh = view_scene(scene, size, size, rs);
  Visibility vis;
  ref::zbuffer_visibility(mesh, rs, vis);
  long covered = 0, wrong = 0;
  for (uint32_t t : vis.tri) {
    if (t == Visibility::kNone) continue;
    ++covered;
    wrong += mesh.tris[t].prim == 0;  // the back plane is the first polygon
  }
  return covered ? double(wrong) / double(covered) : 0;
}

void zfight(Options& o) {
  const int size = o.quick ? 64 : 256;
  std::printf("# zfight: format,near,far_over_near,sep,wrong_fraction (%dx%d, depth 10..100)\n",
              size, size);
  const char* names[] = {"float", "reversed", "fixed24", "double"};
  for (int f = 0; f < 4; ++f)
    for (double near_z : {1e-3, 1e-2, 1e-1, 1.0, 5.0})
      for (double sep : {1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7}) {
        const double w = wrong_fraction(DepthFormat(f), near_z, sep, size);
        // far: the scene's deepest point, about 100 (1 + sep)
        std::printf("%s,%g,%g,%g,%.6f\n", names[f], near_z, 100 / near_z, sep, w);
        if (DepthFormat(f) == DepthFormat::kDouble)
          o.claims.check(w == 0, "double depth never z-fights at sep >= 1e-7");
        if (DepthFormat(f) == DepthFormat::kReversed && sep >= 1e-5)
          o.claims.check(w == 0, "reversed-Z float resolves sep >= 1e-5 at any near plane");
        if (DepthFormat(f) == DepthFormat::kFloat && near_z <= 1e-2 && sep <= 1e-4)
          o.claims.check(w > 0.1,
                "standard float depth with near <= 1e-2 fails sep 1e-4 on over 10% of pixels");
      }
}

// ---------------------------------------------------------------- Gouraud's missed highlights

void gouraud(Options& o) {
  const int size = o.quick ? 96 : 256;
  const std::string s = "v\nfrom 0 0 6\nat 0 0 0\nup 0 1 0\nangle 40\nhither 1\nresolution " +
                        std::to_string(size) + " " + std::to_string(size) +
                        "\nb 0 0 0\nl 2 3 8\nf 0.2 0.4 0.9 0.7 0.8 200 0 1\ns 0 0 0 1.5\n";
  const Input in = scene_input(parse_nff(s, "<shiny sphere>"), "shiny");
  const FamilyImpl& ref = zbuffer().reference();
  std::printf(
      "# gouraud: tess_error,triangles,peak_phong,peak_gouraud,max_error,mean_error (reference, "
      "%dx%d)\n",
      size, size);
  double first = -1, last = 0;
  for (double e : {8.0, 4.0, 2.0, 1.0, 0.5, 0.25, 0.125}) {
    FrameOptions fo;
    fo.width = fo.height = size;
    fo.params.set("tess_error", std::to_string(e));
    FrameOptions go = fo;
    fo.params.set("shading", "phong");
    go.params.set("shading", "gouraud");
    FrameStats st;
    const Image p = ref.run_as<Image>(in, fo, &st), g = ref.run_as<Image>(in, go, &st);
    const ScreenMesh mesh =
        view_scene(input_as<Scene>(in), size, size, raster_settings(fo.params, "shiny"));
    double peak_p = 0, peak_g = 0;
    for (int j = 0; j < size; ++j)
      for (int i = 0; i < size; ++i) {
        peak_p = std::max(peak_p, double(p.pixel(i, j)[0]));
        peak_g = std::max(peak_g, double(g.pixel(i, j)[0]));
      }
    const ImageError err = compare_images(g, p);
    std::printf("%g,%llu,%.4f,%.4f,%.4f,%.6f\n", e, (unsigned long long)mesh.sphere_tris, peak_p,
                peak_g, err.max_error, err.mean_error);
    if (first < 0) first = err.max_error;
    last = err.max_error;
  }
  o.claims.check(first > 0.2, "coarse Gouraud misses the highlight by over 0.2");
  o.claims.check(last < first / 2, "Gouraud's highlight error halves from tess_error 8 to 1/8");
}

// ---------------------------------------------------------------- the painter's failure map

void painter(Options& o) {
  const Family& f = *registry().find("painter");
  const int cases = o.quick ? 20 : 300;
  std::printf(
      "# painter: kind,case,wrong_fraction,wrong_pixels,reported,wrong_split (reference, 64x64, "
      "flat)\n");
  for (const char* kind : {"cyclic_triple", "interpenetrating_pair"}) {
    int unreported = 0, split_wrong = 0, right = 0;
    const std::vector<PainterMapCase> map = painter_failure_map(f.reference(), kind, cases, 7);
    for (size_t n = 0; n < map.size(); ++n) {
      const PainterMapCase& c = map[n];
      std::printf("%s,%zu,%.6f,%d,%d,%d\n", kind, n, c.wrong_fraction, c.wrong, int(c.reported),
                  c.wrong_split);
      unreported += c.wrong > 0 && !c.reported;
      split_wrong += c.wrong_split > 0;
      right += c.wrong == 0;
    }
    o.claims.check(unreported == 0, std::string("the painter reports every ") + kind + " it draws wrong");
    o.claims.check(split_wrong == 0, std::string("with split, every ") + kind + " equals the z-buffer");
    if (kind == std::string("cyclic_triple"))
      o.claims.check(right == 0, "no cyclic triple is drawn right");
  }
}

}  // namespace

}  // namespace lockstep::props::raster

int main(int argc, char** argv) {
  using namespace lockstep::props::raster;
  Options o;
  std::string which;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--quick"))
      o.quick = true;
    else if (!std::strcmp(argv[i], "--impl") && i + 1 < argc)
      o.impl = argv[++i];
    else if (which.empty() && argv[i][0] != '-')
      which = argv[i];
    else {
      std::fprintf(
          stderr,
          "usage: lockstep_raster_study tessellation|supersampling|zfight|gouraud|painter|all "
          "[--quick] [--impl NAME]\n");
      return 2;
    }
  }
  if (which.empty()) which = "all";
  bool any = false;
  auto run = [&](const char* name, void (*f)(Options&)) {
    if (which == "all" || which == name) {
      f(o);
      any = true;
    }
  };
  run("tessellation", tessellation);
  run("supersampling", supersampling);
  run("zfight", zfight);
  run("gouraud", gouraud);
  run("painter", painter);
  if (!any) {
    std::fprintf(stderr, "lockstep_raster_study: unknown study '%s'\n", which.c_str());
    return 2;
  }
  return o.claims.exit_code();
}

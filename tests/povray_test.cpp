// The ray_trace family's povray row (POV-Ray 3.7 run as a process,
// optimized/ray_trace_povray.cpp) against the reference, per pixel, on what
// both models define the same way:
//
//   * visibility and coverage: an identity copy of the scene (one material
//     per primitive whose colour encodes its index, drawn by the ambient term
//     alone: kd = 10, so 0.1 kd = 1, no lights; the reference draws the same
//     copy) must show the same primitive in every pixel, or the background
//     in both;
//   * which lights reach each point: a diffuse-white copy (colour 1, kd 1,
//     ks 0, depth 1), one POV-Ray frame per light with that light alone: a
//     pixel is lit when its value is above the ambient 0.1 by more than
//     half the terminator band, the reference's (its frame of the same copy)
//     by more than kLitThreshold: only an unblocked shadow ray with N.L > 0
//     lights a point (core/ray_trace.h).
// Both copies make every polygon two-sided (T = 1e-9: NFF's rule,
// core/shading.h visible_side, with no transmitted ray at depth 1 and a
// negligible transmit in POV-Ray), because POV-Ray draws both sides of every
// surface; how many pixels NFF's one-sidedness changes is measured apart
// (one_sided below) and printed.
//
// Excluded but counted: edge pixels (within 1 pixel of a change of the
// reference's primitive, coverage or, per light, lit state: silhouettes and
// shadow edges, where a rounding decides) and terminator pixels (the
// reference's |N.L| < kTerminator, where the two models' smooth-triangle
// normals decide).
//
//   * Agree.*: 64x64 corpus scenes (balls-2: spheres; teapot-2: patches;
//     tree-2: cones and polygons): agreement on at least kMinAgree of the
//     compared pixels, for visibility and for each light;
//   * Mutant.*: POV-Ray given the scene mirrored about the plane of the view
//     direction and up (the image mirrored left-right, as a camera with right
//     negated) or every light moved must fall below it (balls-2: lit/dark
//     58.9% for one light, N.L 9.4%; lights moved: N.L 4.0%);
//   * DISABLED_Figures: the corpus' rt-pov-* SPD scenes at 128x128 (run with
//     --gtest_also_run_disabled_tests; the figures in registry/ray_trace_row.cpp and
//     README.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/family.h"
#include "core/image.h"
#include "core/ray_trace.h"
#include "core/shading.h"
#include "core/timer.h"
#include "optimized/ray_trace_povray.h"
#include "registry/loaders.h"
#include "reference/ray_trace.h"

namespace lockstep {
namespace {

constexpr double kLitThreshold = 1.0 / 512;  // above the ambient, on a light of intensity 1
constexpr double kTerminator = 0.01;         // the reference's N.L below this when lit: excluded
// The bound: measured 100% on the three scenes' visibility, every light's
// lit/dark and N.L (worst N.L difference 0.00/255; edge pixels, not judged,
// agree on 99.8-100%), and on the seven rt-pov-* SPD scenes at 128x128.
// Injected into the row's writer, right negated fails (balls-2 58.9%,
// teapot-2 65.2%) and light positions scaled by 1.02 fail on N.L (83.2%).
constexpr double kMinAgree = 0.999;
constexpr double kDiffuseAbs = 1.0 / 255;

Scene load(const std::string& file) {
  return input_as<Scene>(load_nff(std::string(LOCKSTEP_CORPUS_DIR) + "/scenes/" + file));
}

// Every material white and diffuse (two-sided, see above).
Scene white_copy(const Scene& s, double transmittance = 1e-9) {
  Scene w = s;
  for (Material& m : w.materials) m = Material{{1, 1, 1}, 1.0, 0.0, 1.0, transmittance, 1.0};
  w.background = {0, 0, 0};
  return w;
}

// One material per primitive, its colour the index + 1 in base 255 (8 bits
// per channel: exact through POV-Ray's 16-bit output), ambient only.
Scene identity_copy(const Scene& s, double transmittance = 1e-9) {
  Scene w = s;
  w.lights.clear();
  w.background = {0, 0, 0};
  w.materials.clear();
  auto mat = [&](uint32_t prim) {
    const uint32_t k = prim + 1;
    Material m{{double(k % 256) / 255, double((k / 256) % 256) / 255, double(k / 65536) / 255}, 10.0, 0.0, 1.0,
               transmittance, 1.0};
    return add_material(w, m);
  };
  for (uint32_t i = 0; i < s.sphere_count(); ++i) w.sphere_material[i] = mat(i);
  for (uint32_t p = 0; p < s.polygon_count(); ++p) w.poly_material[p] = mat(s.sphere_count() + p);
  for (uint32_t c = 0; c < s.cone_count(); ++c) w.cone_material[c] = mat(s.cone_first_prim() + c);
  return w;
}

uint32_t decode(const float* p) {
  const auto b = [](float v) { return uint32_t(std::lround(double(v) * 255)); };
  const uint32_t k = b(p[0]) + 256 * b(p[1]) + 65536 * b(p[2]);
  return k == 0 ? Hit::kNoHit : k - 1;
}

FrameOptions options(int size, int depth) {
  FrameOptions o;
  o.width = o.height = size;
  o.threads = 2;
  o.params.set("depth", std::to_string(depth));
  return o;
}

// The reference's decisions per pixel, from its frames of the same copies:
// the primitive seen (identity copy), and per light (white copy, that light
// alone at intensity 1) lit (value above the ambient by more than
// kLitThreshold) and N.L (that value less the ambient: N.L when lit, 0 when
// not).
struct RefMaps {
  int w = 0, h = 0;
  std::vector<uint32_t> prim;
  std::vector<std::vector<uint8_t>> lit;
  std::vector<std::vector<double>> ndotl;
};

Scene one_light(const Scene& white, size_t k) {
  Scene one = white;
  one.lights = {white.lights[k]};
  one.lights[0].has_color = false;  // intensity 1: 1/sqrt(1)
  return one;
}

std::vector<uint32_t> prims_of(const Image& img) {
  std::vector<uint32_t> out(size_t(img.width) * img.height);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) out[size_t(y) * img.width + x] = decode(img.pixel(x, y));
  return out;
}

RefMaps reference_maps(const Scene& scene, int size, double transmittance = 1e-9) {
  RefMaps r;
  r.w = r.h = size;
  FrameStats st;
  r.prim = prims_of(ref::trace_render(identity_copy(scene, transmittance), options(size, 1), &st));
  const Scene white = white_copy(scene, transmittance);
  for (size_t k = 0; k < white.lights.size(); ++k) {
    const Image img = ref::trace_render(one_light(white, k), options(size, 1), &st);
    std::vector<uint8_t> lit(r.prim.size());
    std::vector<double> ndotl(r.prim.size());
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x) {
        const double v = double(img.pixel(x, y)[0]) - kAmbient;
        lit[size_t(y) * size + x] = v > kLitThreshold;
        ndotl[size_t(y) * size + x] = v > kLitThreshold ? v : 0;
      }
    r.lit.push_back(std::move(lit));
    r.ndotl.push_back(std::move(ndotl));
  }
  return r;
}

struct Count {
  long pixels = 0, edge = 0, terminator = 0, compared = 0, agree = 0;
  long edge_agree = 0;  // edge pixels that agree all the same (not judged)
  double fraction() const { return compared ? double(agree) / double(compared) : 1.0; }
  std::string str() const {
    char b[200];
    std::snprintf(b, sizeof b, "%.4f%% of %ld compared (%ld edge, %.1f%% of them agreeing; %ld terminator excluded; of %ld)",
                  100 * fraction(), compared, edge, edge ? 100.0 * double(edge_agree) / double(edge) : 100.0,
                  terminator, pixels);
    return b;
  }
};

// An edge pixel: one of its 8 neighbours (or itself) differs in key.
template <class Key>
bool near_change(int w, int h, int x, int y, Key key) {
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const int u = x + dx, v = y + dy;
      if (u < 0 || v < 0 || u >= w || v >= h) continue;
      if (key(u, v) != key(x, y)) return true;
    }
  return false;
}

struct Result {
  Count visibility;
  std::vector<Count> lights;
  // Lit in both, not edge: N.L (the value less the ambient, light of
  // intensity 1, white, kd 1) within kDiffuseAbs of the reference's.
  Count diffuse;
  double diffuse_worst = 0;
  long one_sided = 0;  // pixels whose primitive NFF's one-sidedness changes
  double seconds = 0;
  double worst() const {
    double f = visibility.fraction();
    for (const Count& c : lights) f = std::min(f, c.fraction());
    return std::min(f, diffuse.fraction());
  }
  std::string str() const {
    std::string s = "visibility " + visibility.str();
    for (size_t k = 0; k < lights.size(); ++k) s += "\n  light " + std::to_string(k + 1) + ": " + lights[k].str();
    char b[80];
    std::snprintf(b, sizeof b, " (worst %.2f/255)", 255 * diffuse_worst);
    s += "\n  diffuse N.L within 1/255: " + diffuse.str() + b;
    s += "\n  one-sided NFF polygons change " + std::to_string(one_sided) + " pixels";
    return s;
  }
};

// A mutation of what POV-Ray is given (the reference always gets the scene).
enum class Mutant { kNone, kMirror, kLightOff };

Scene mutate(Scene s, Mutant m) {
  if (m == Mutant::kMirror) {
    // The image mirrored left-right: the eye reflected through the plane of
    // view direction and up, which is the same camera with right negated.
    const Camera c = Camera::from_view(s.view, 64, 64);
    auto reflect_point = [&](const Vec3& p) { return p - 2.0 * dot(p - c.eye, c.right) * c.right; };
    for (Vec3& v : s.sphere_center) v = reflect_point(v);
    for (Vec3& v : s.vertex) v = reflect_point(v);
    for (Vec3& v : s.vertex_normal) v = v - 2.0 * dot(v, c.right) * c.right;
    for (Vec3& v : s.cone_base) v = reflect_point(v);
    for (Vec3& v : s.cone_apex) v = reflect_point(v);
    for (Light& l : s.lights) l.position = reflect_point(l.position);
    for (Plane& p : s.poly_plane) {
      p.n = p.n - 2.0 * dot(p.n, c.right) * c.right;
    }
  }
  if (m == Mutant::kLightOff)
    for (Light& l : s.lights) l.position = l.position + 0.2 * length(l.position - s.view.at) * Vec3{0.6, 0, 0.8};
  return s;
}

Result compare(const Scene& scene, int size, Mutant mutant = Mutant::kNone) {
  Result res;
  const Stopwatch sw;
  const Scene white = white_copy(scene);
  const RefMaps ref = reference_maps(scene, size);
  const int w = size, h = size;
  auto prim_at = [&](int x, int y) { return ref.prim[size_t(y) * w + x]; };
  // Visibility and coverage.
  {
    FrameStats st;
    const Image pov = opt::povray::trace_render(mutate(identity_copy(scene), mutant), options(size, 1), &st);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        ++res.visibility.pixels;
        if (near_change(w, h, x, y, prim_at)) {
          ++res.visibility.edge;
          res.visibility.edge_agree += decode(pov.pixel(x, y)) == prim_at(x, y);
          continue;
        }
        ++res.visibility.compared;
        if (decode(pov.pixel(x, y)) == prim_at(x, y)) ++res.visibility.agree;
      }
  }
  // One light at a time.
  for (size_t k = 0; k < white.lights.size(); ++k) {
    FrameStats st;
    const Image pov = opt::povray::trace_render(mutate(one_light(white, k), mutant), options(size, 1), &st);
    Count c;
    const auto& lit = ref.lit[k];
    auto key = [&](int x, int y) {
      const size_t i = size_t(y) * w + x;
      return uint64_t(ref.prim[i]) * 2 + lit[i];
    };
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const size_t i = size_t(y) * w + x;
        ++c.pixels;
        // Lit in POV-Ray: clearly above the ambient (half the terminator band:
        // a dark pixel of the reference whose N.L is just below 0 may be
        // just above 0 with POV-Ray's normals).
        const bool pov_lit = double(pov.pixel(x, y)[0]) - kAmbient > 0.5 * kTerminator;
        if (near_change(w, h, x, y, key)) {
          ++c.edge;
          c.edge_agree += pov_lit == bool(lit[i]);
          continue;
        }
        if (lit[i] && ref.ndotl[k][i] < kTerminator) {
          ++c.terminator;
          continue;
        }
        ++c.compared;
        if (pov_lit == bool(lit[i])) ++c.agree;
        if (pov_lit && lit[i]) {
          const double e = std::abs(double(pov.pixel(x, y)[0]) - kAmbient - ref.ndotl[k][i]);
          ++res.diffuse.pixels;
          ++res.diffuse.compared;
          res.diffuse.agree += e <= kDiffuseAbs;
          res.diffuse_worst = std::max(res.diffuse_worst, e);
        }
      }
    res.lights.push_back(c);
  }
  // NFF's one-sidedness: the reference's primitives with the copy's polygons
  // one-sided (T = 0) against two-sided.
  {
    FrameStats st;
    const std::vector<uint32_t> one_sided =
        prims_of(ref::trace_render(identity_copy(scene, 0.0), options(size, 1), &st));
    for (size_t i = 0; i < ref.prim.size(); ++i) res.one_sided += one_sided[i] != ref.prim[i];
  }
  res.seconds = sw.seconds();
  return res;
}

class Agree : public ::testing::TestWithParam<const char*> {};

TEST_P(Agree, VisibilityAndLights) {
  if (!opt::povray::available()) GTEST_SKIP() << "no povray row in this build";
  const Result r = compare(load(GetParam()), 64);
  std::printf("%s 64x64: %s\n  (%.2f s)\n", GetParam(), r.str().c_str(), r.seconds);
  EXPECT_GE(r.visibility.fraction(), kMinAgree) << r.str();
  for (const Count& c : r.lights) EXPECT_GE(c.fraction(), kMinAgree) << r.str();
  EXPECT_GE(r.diffuse.fraction(), kMinAgree) << r.str();
}
INSTANTIATE_TEST_SUITE_P(Corpus, Agree, ::testing::Values("balls-2.nff", "teapot-2.nff", "tree-2.nff"),
                         [](const auto& info) {
                           std::string n = info.param;
                           n = n.substr(0, n.find('.'));
                           std::replace(n.begin(), n.end(), '-', '_');
                           return n;
                         });

// The check can fail: a mirrored image or moved lights fall below the bound.
TEST(Mutant, MirroredCamera) {
  if (!opt::povray::available()) GTEST_SKIP() << "no povray row in this build";
  const Result r = compare(load("balls-2.nff"), 64, Mutant::kMirror);
  std::printf("balls-2 mirrored: %s\n", r.str().c_str());
  EXPECT_LT(r.worst(), kMinAgree) << r.str();
}
TEST(Mutant, LightMoved) {
  if (!opt::povray::available()) GTEST_SKIP() << "no povray row in this build";
  const Result r = compare(load("balls-2.nff"), 64, Mutant::kLightOff);
  std::printf("balls-2 lights moved: %s\n", r.str().c_str());
  EXPECT_LT(r.worst(), kMinAgree) << r.str();
}

// The corpus' rt-pov-* SPD scenes at 128x128, and the row's full-colour
// difference from the reference at the manifest's depth.
TEST(DISABLED_Figures, CorpusSpd) {
  if (!opt::povray::available()) GTEST_SKIP() << "no povray row in this build";
  const std::pair<const char*, int> cases[] = {{"balls-4", 3}, {"gears-4", 3}, {"mount-6", 3}, {"rings-7", 2},
                                               {"teapot-6", 3}, {"tetra-6", 3}, {"tree-11", 2}};
  for (const auto& [name, depth] : cases) {
    std::optional<Input> in = load_spd(name);
    ASSERT_TRUE(in) << name;
    const Scene& s = input_as<Scene>(*in);
    const Result r = compare(s, 128);
    std::printf("%s 128x128: %s\n  (%.1f s)\n", name, r.str().c_str(), r.seconds);
    const FrameOptions o = options(128, depth);
    FrameStats a, b;
    const Image ref = ref::trace_render(s, o, &a);
    const Image pov = opt::povray::trace_render(s, o, &b);
    long over2 = 0, over8 = 0, over32 = 0;
    double worst = 0, sum = 0;
    for (int y = 0; y < 128; ++y)
      for (int x = 0; x < 128; ++x) {
        double e = 0;
        for (int c = 0; c < 3; ++c)
          e = std::max(e, std::abs(double(ref.pixel(x, y)[c]) - double(pov.pixel(x, y)[c])));
        over2 += e > 2.0 / 255;
        over8 += e > 8.0 / 255;
        over32 += e > 32.0 / 255;
        worst = std::max(worst, e);
        sum += e;
      }
    std::printf("  colour depth %d: mean %.2f/255, worst %.1f/255, over 2/255 %.2f%%, "
                "8/255 %.2f%%, 32/255 %.2f%%; %s\n",
                depth, 255 * sum / 16384, 255 * worst, 100.0 * over2 / 16384, 100.0 * over8 / 16384,
                100.0 * over32 / 16384, b.notes.empty() ? "" : b.notes.front().c_str());
  }
}

}  // namespace
}  // namespace lockstep

// lockstep props/raster: the simd z-buffer's hidden-sphere skipping
// (optimized/zbuffer/zbuffer_occlusion.h, OcclusionMap) changes nothing but the time.
//
//   HiddenSkipped.zbuffer__simd   Random clusters of spheres (big ones in front,
//       small ones behind and between, some inside out, some crossing the
//       hither plane) at random tessellation errors (coarse meshes: the inner
//       ball is then far inside the sphere), culling modes, depth formats,
//       shadings and sample counts: the image with hidden=skip equals the
//       image with hidden=draw bit for bit (colour and depth). Unit: pixels
//       that differ; bound 0.
//   HiddenSkipped.zbuffer__simd_corpus   The corpus' sphere scenes (balls,
//       shells) at 256^2 and 512^2, every culling mode and depth format, and
//       at 1024^2 with world culling and float depth: the
//       same equality, and hidden triangles are actually skipped (a skip that
//       never happens would pass the equality trivially).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>

#include "io/nff.h"
#include "optimized/zbuffer/zbuffer_simd.h"
#include "props/gen/numbers.h"
#include "props/raster/parts.h"

namespace lockstep::props::raster {

namespace {

rc::Gen<RasterCase> sphere_cluster() {
  return rc::gen::exec([] {
    RasterCase c;
    c.width = *rc::gen::inRange(24, 97);
    c.height = *rc::gen::inRange(24, 97);
    std::string s = "v\nfrom 0 0 0\nat 0 0 -1\nup 0 1 0\nangle 40\nhither 1\nresolution " +
                    std::to_string(c.width) + " " + std::to_string(c.height) + "\nb 0.1 0.2 0.3\n";
    s += "l " + num(*rc::gen::inRange(-10, 11)) + " " + num(*rc::gen::inRange(-10, 11)) + " 4\n";
    const double half = std::tan(20.0 * M_PI / 180.0);
    const int n = *rc::gen::inRange(2, 25);
    for (int k = 0; k < n; ++k) {
      // The first few big and near, the rest anywhere behind or between.
      const bool big = k < 3;
      const double z = big ? *gen::uniform(1.5, 6) : *gen::uniform(1.2, 14);
      const double r = (big ? *gen::uniform(0.3, 1.2) : *gen::log_uniform(0.01, 0.4)) * half * z;
      const double x = *gen::uniform(-1.1, 1.1) * half * z, y = *gen::uniform(-1.1, 1.1) * half * z;
      const bool inverted = *rc::gen::inRange(0, 6) == 0;
      s += "f " + num(*gen::uniform(0.2, 1)) + " " + num(*gen::uniform(0.2, 1)) + " " +
           num(*gen::uniform(0.2, 1)) + " 0.8 0.3 8 0 1\n";
      s += "s " + num(x) + " " + num(y) + " " + num(-z) + " " + num(inverted ? -r : r) + "\n";
    }
    c.nff = s;
    c.params.set("shading", *rc::gen::element<std::string>("flat", "phong"));
    c.params.set("cull", *rc::gen::element<std::string>("world", "projection", "none"));
    c.params.set("depth", *rc::gen::element<std::string>("float", "reversed", "fixed24", "double"));
    c.params.set("spp", *rc::gen::element<std::string>("1", "1", "4"));
    c.params.set("tess_error", *rc::gen::element<std::string>("0.25", "1", "4", "16"));
    return c;
  });
}

struct Pair {
  Image skip, draw;
  uint64_t skipped = 0;
};

Pair render_both(const Scene& scene, FrameOptions o) {
  Pair p;
  FrameStats stats;
  o.params.set("hidden", "skip");
  p.skip = opt::simd::zbuffer(scene, o, &stats);
  p.skipped = stats.skipped;
  o.params.set("hidden", "draw");
  p.draw = opt::simd::zbuffer(scene, o, nullptr);
  return p;
}

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// One outcome per pixel: unexplained where colour or depth differ in any bit.
Verdict compare(const Pair& p) {
  Verdict v;
  const int w = p.skip.width, h = p.skip.height;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * size_t(w) + size_t(x);
      Outcome o;
      bool same = same_bits(p.skip.depth[i], p.draw.depth[i]);
      double err = 0;
      for (int c = 0; c < 4; ++c) {
        same = same && same_bits(p.skip.rgba[4 * i + size_t(c)], p.draw.rgba[4 * i + size_t(c)]);
        err = std::max(err, double(std::fabs(p.skip.rgba[4 * i + size_t(c)] - p.draw.rgba[4 * i + size_t(c)])));
      }
      if (!same) {
        o.kind = Outcome::unexplained;
        o.label = "differs";
        o.err = err;
        char buf[240];
        std::snprintf(buf, sizeof buf,
                      "pixel (%d, %d): skip rgb %.9g %.9g %.9g depth %.9g, draw rgb %.9g %.9g %.9g depth "
                      "%.9g (%llu triangles skipped)",
                      x, y, p.skip.rgba[4 * i], p.skip.rgba[4 * i + 1], p.skip.rgba[4 * i + 2],
                      double(p.skip.depth[i]), p.draw.rgba[4 * i], p.draw.rgba[4 * i + 1],
                      p.draw.rgba[4 * i + 2], double(p.draw.depth[i]), (unsigned long long)p.skipped);
        o.detail = buf;
      }
      v.rays.push_back(o);
    }
  return v;
}

Verdict cluster_case(const RasterCase& c) {
  const auto scene = c.scene();
  return compare(render_both(*scene, c.options()));
}

void corpus_cases() {
  uint64_t skipped_total = 0;
  for (const char* name : {"balls-3", "shells-1"}) {
    const Scene scene = read_nff(std::string(LOCKSTEP_CORPUS_DIR) + "/scenes/" + name + ".nff");
    for (int size : {256, 512, 1024})
      for (const char* cull : {"world", "projection", "none"})
        for (const char* depth : {"float", "reversed", "fixed24", "double"}) {
          // (1024^2, the benchmarks' size, where the most is hidden: world
          // culling and float depth only. A pair of cells misread there
          // changed 18 of balls-3's pixels and none at the smaller sizes.)
          if (size == 1024 && (std::strcmp(cull, "world") != 0 || std::strcmp(depth, "float") != 0))
            continue;
          FrameOptions o;
          o.width = o.height = size;
          o.threads = 2;
          o.params.set("shading", "flat");
          o.params.set("cull", cull);
          o.params.set("depth", depth);
          const Pair p = render_both(scene, o);
          const Verdict v = compare(p);
          EXPECT_TRUE(v.passed()) << name << " " << size << "^2 cull=" << cull << " depth=" << depth << ": "
                                  << v.count(Outcome::unexplained) << " pixels differ; first: " << v.first_failure();
          skipped_total += p.skipped;
          if (std::string(name) == "shells-1") {
            EXPECT_GT(p.skipped, 0u) << name << " " << size << "^2 cull=" << cull << " depth=" << depth
                                     << ": no hidden triangle skipped";
          }
        }
  }
  std::printf("HiddenSkipped corpus: %llu triangles skipped over 50 frames\n",
              (unsigned long long)skipped_total);
}

}  // namespace

void hidden_part(const Family& family, FamilyProperties& out) {
  const FamilyImpl* simd = family.find("simd");
  if (!simd) return;
  Property p = case_property(family, *simd, "HiddenSkipped", "sphere_cluster", sphere_cluster(), 0,
                             "pixels differing", cluster_case);
  out.properties.push_back(std::move(p));
  out.fixed.push_back({"HiddenSkipped", "zbuffer__simd_corpus", corpus_cases});
}

}  // namespace lockstep::props::raster

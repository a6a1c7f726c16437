// lockstep props/raster: of equal depths the first drawn stays (core/raster.h:
// nearer() is strict; reference/zbuffer.cpp "the first of equal depths stays").
//
//   FirstDrawnWins.<family>__<impl>   (part "first_drawn"; the zbuffer and
//       scanline families, every row of each, llvmpipe where it is built)
//       Coplanar duplicates: one triangle drawn two or three times, the same
//       vertices (so the same depth at every sample in any arithmetic), each
//       copy in its own pure colour (red, green or blue, Ks = 0: every lit
//       pixel of a copy has only its own channel). On every covered pixel the
//       FIRST copy in the scene must show, for every depth format
//       (float|reversed|fixed24|double), every draw order (order=auto|mesh|
//       reverse: the simd z-buffer's tiles then draw in mesh order, ties
//       losing, or reversed, ties winning) and both a flat and a per-sample
//       shading (flat: the simd z-buffer's forward path), where the row draws
//       it (FamilyImpl::unsupported: llvmpipe draws flat only here, and
//       with its own 24-bit depth buffer and GL_LESS whatever depth= says).
//       24 seeded scenes, 40 x 40, the triangles partly off screen.
//
// Before this, only CoverageAgreement's tie_order (visibility.cpp) caught a
// depth test that lets a tie through in mesh order (`>=` for `>` in the
// reversed test of optimized/zbuffer/zbuffer_raster_kernels.cpp's Closer): here every
// row is held to the rule directly, on whole frames.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>
#include <string>

#include "props/raster/parts.h"

namespace lockstep::props::raster {

namespace {

constexpr int kScenes = 24;
constexpr int kSize = 40;
const char* const kChannel[3] = {"red", "green", "blue"};

struct Dup {
  std::string nff;
  int copies = 2;
  int colour[3] = {0, 1, 2};  // copy q's channel
};

// One triangle in front of the eye (depths 2..12 per vertex: a tilted
// plane), facing it, mostly in view; copies drawn in the order given.
Dup make_dup(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0, 1);
  Dup d;
  d.copies = 2 + int(rng() % 2);
  const int first = int(rng() % 3), step = 1 + int(rng() % 2);
  for (int q = 0; q < 3; ++q) d.colour[q] = (first + q * step) % 3;
  const double half = std::tan(22.5 * M_PI / 180);
  Vec3 v[3];
  for (Vec3& p : v) {
    const double z = 2 + 10 * u(rng);
    p = {(2 * u(rng) - 1) * 1.4 * half * z, (2 * u(rng) - 1) * 1.4 * half * z, -z};
  }
  // Counter-clockwise seen from the eye at the origin (NFF's front).
  if (dot(cross(v[1] - v[0], v[2] - v[0]), -v[0]) < 0) std::swap(v[1], v[2]);
  std::ostringstream s;
  s.precision(17);
  s << "v\nfrom 0 0 0\nat 0 0 -1\nup 0 1 0\nangle 45\nhither 0.1\nresolution " << kSize << " "
    << kSize << "\nb 0 0 0\nl 0 0 0\n";
  for (int q = 0; q < d.copies; ++q) {
    const int c = d.colour[q];
    s << "f " << (c == 0) << " " << (c == 1) << " " << (c == 2) << " 0.8 0 1 0 1\np 3\n";
    for (const Vec3& p : v) s << p.x << " " << p.y << " " << p.z << "\n";
  }
  d.nff = s.str();
  return d;
}

void first_drawn_wins(const Family& family, const FamilyImpl& impl) {
  const uint64_t seed = 0xf1257d4a3ULL;
  std::mt19937_64 rng(seed);
  long covered = 0, frames = 0, refused = 0;
  for (int n = 0; n < kScenes; ++n) {
    const Dup dup = make_dup(rng);
    RasterCase c;
    c.nff = dup.nff;
    c.width = c.height = kSize;
    const auto scene = c.scene();
    const Input in = make_input<Scene>(*scene, "<first_drawn>", kSize, kSize, scene->background);
    for (const char* depth : {"float", "reversed", "fixed24", "double"})
      for (const char* order : {"auto", "mesh", "reverse"})
        for (const char* shading : {"flat", "phong"}) {
          FrameOptions o = c.options();
          o.params.set("depth", depth);
          o.params.set("order", order);
          o.params.set("shading", shading);
          if (impl.unsupported && !impl.unsupported(o.params).empty()) {
            ++refused;
            continue;
          }
          const Image img = impl.run_as<Image>(in, o, nullptr);
          ++frames;
          int bad = 0;
          for (int y = 0; y < kSize; ++y)
            for (int x = 0; x < kSize; ++x) {
              if (!std::isfinite(img.depth[size_t(y) * kSize + size_t(x)])) continue;
              ++covered;
              const float* p = img.pixel(x, y);
              int shown = 0;
              for (int ch = 1; ch < 3; ++ch)
                if (p[ch] > p[shown]) shown = ch;
              const int want = dup.colour[0];
              bool ok = p[want] > 0;
              for (int ch = 0; ch < 3; ++ch) ok = ok && (ch == want || p[ch] == 0.0f);
              if (ok) continue;
              int copy = -1;
              for (int q = 0; q < dup.copies; ++q)
                if (dup.colour[q] == shown) copy = q;
              if (++bad <= 3)
                ADD_FAILURE() << family.name << " " << impl.name << ": seed " << seed << " scene "
                              << n << ", depth=" << depth << " order=" << order
                              << " shading=" << shading << ": pixel (" << x << ", " << y
                              << ") shows " << kChannel[shown] << " (copy " << copy + 1 << " of "
                              << dup.copies << ") as (" << p[0] << ", " << p[1] << ", " << p[2]
                              << "), depth " << img.depth[size_t(y) * kSize + size_t(x)]
                              << "; the first copy drawn (" << kChannel[want]
                              << ") must win every tie\n"
                              << write_case(c);
            }
          if (bad > 3)
            ADD_FAILURE() << family.name << " " << impl.name << ": scene " << n
                          << ", depth=" << depth << " order=" << order << " shading=" << shading
                          << ": " << bad << " pixels in all";
        }
  }
  std::printf(
      "[ lockstep ] FirstDrawnWins.%s__%s: seed %llu, %ld frames (%ld settings it does not draw), "
      "%ld "
      "covered pixels checked\n",
      std::string(family.name).c_str(), std::string(impl.name).c_str(), (unsigned long long)seed,
      frames, refused, covered);
  // Something was drawn: a test of ties needs covered pixels.
  EXPECT_GT(covered, long(frames) * kSize * kSize / 20);
}

}  // namespace

void first_drawn_part(const Family& family, FamilyProperties& out) {
  for (const FamilyImpl& impl : family.impls) {
    const Family* f = &family;
    const FamilyImpl* ip = &impl;
    out.fixed.push_back({"FirstDrawnWins", std::string(family.name) + "__" + std::string(impl.name),
                         [f, ip] { first_drawn_wins(*f, *ip); }});
  }
}

}  // namespace lockstep::props::raster

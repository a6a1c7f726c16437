// Tests of lockstep's NFF light extension (io/nff.h): '#lockstep atten' and
// '#lockstep spot'.
//
//   * parsing: the fields land in the Light, the direction is normalised, only
//     a first word of exactly "#lockstep" is special;
//   * closed form: a diffuse floor (the plane z = 0, normal +z, ks = 0) seen
//     from straight above, lit by one spot with attenuation. For every pixel
//     the expected colour is written out here from the formulas of Foley et
//     al. 16.1.4 and Warn (1983), independently of core/shading.cpp:
//       I = 0.1 kd C + Ip f_att(d) spot(L) kd C (N.L)
//     with p the exact hit of the pixel's centre ray on the plane. Every
//     ray-casting implementation must reproduce it: the reference (double)
//     within kRefBound, the float SIMD shading of simd and embree within
//     kOptBound (measured figures in the messages). Each configuration also
//     checks that it discriminates: dropping the attenuation, the min(1, .),
//     the exponent or the cone would move some pixel by far more than the bounds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <ostream>
#include <string>

#include "core/camera.h"
#include "core/error.h"
#include "io/nff.h"
#include "core/shading.h"
#include "optimized/ray_cast_simd.h"
#include "optimized/ray_cast_embree.h"
#include "reference/ray_cast.h"

namespace lockstep {
namespace {

// ---------------------------------------------------------------- parsing

const char* kView = "v\nfrom 0 0 10\nat 0 0 0\nup 0 1 0\nangle 60\nhither 0.01\nresolution 41 41\n";

TEST(NffLights, FieldsAreRead) {
  const Scene s = parse_nff(std::string(kView) +
                                "l 1 2 3\n"
                                "#lockstep spot 0 0 -2 25 4   # a trailing comment\n"
                                "\n"
                                "# an ordinary comment between\n"
                                "  #lockstep atten 0.5 0.25 0.125\n"
                                "l 4 5 6 1 1 1\n"
                                "#lockstep atten 1 0 1e-3\n"
                                "l 7 8 9\n",
                            "fields.nff");
  ASSERT_EQ(s.lights.size(), 3u);
  const Light& a = s.lights[0];
  EXPECT_TRUE(a.spot);
  EXPECT_EQ(a.spot_dir, (Vec3{0, 0, -1}));  // normalised
  EXPECT_EQ(a.spot_cutoff, 25.0);
  EXPECT_EQ(a.spot_exponent, 4.0);
  EXPECT_EQ(a.atten, (Vec3{0.5, 0.25, 0.125}));
  const Light& b = s.lights[1];
  EXPECT_FALSE(b.spot);
  EXPECT_EQ(b.atten, (Vec3{1, 0, 1e-3}));
  const Light& c = s.lights[2];  // untouched: an ordinary point light
  EXPECT_FALSE(c.spot);
  EXPECT_EQ(c.atten, (Vec3{1, 0, 0}));
}

TEST(NffLights, OnlyExactHashLockstepIsSpecial) {
  // Ordinary comments, even ones that look like the extension, stay comments.
  const Scene s = parse_nff(std::string(kView) +
                                "l 1 2 3\n"
                                "# lockstep atten 0 0 0\n"
                                "#lockstepx atten 0 0 0\n"
                                "#LOCKSTEP atten 0 0 0\n"
                                "l 1 2 3 # #lockstep atten 0 0 0\n",
                            "comments.nff");
  ASSERT_EQ(s.lights.size(), 2u);
  for (const Light& l : s.lights) {
    EXPECT_FALSE(l.spot);
    EXPECT_EQ(l.atten, (Vec3{1, 0, 0}));
  }
}

TEST(NffLights, TinyAndHugeDirectionsNormalise) {
  for (const char* d : {"0 0 -1e-310", "0 0 -1e300", "3e-200 0 -4e-200"}) {
    const Scene s =
        parse_nff(std::string(kView) + "l 1 2 3\n#lockstep spot " + d + " 30 1\n", "dir.nff");
    const Vec3 u = s.lights[0].spot_dir;
    EXPECT_NEAR(length(u), 1.0, 1e-15) << d;
    EXPECT_LT(u.z, 0) << d;
  }
}

TEST(NffLights, MalformedIsAnInputErrorNamingTheLine) {
  // The CLI tests (tests/bad/) check each message; here: every form throws
  // InputError at line 9, the #lockstep line.
  for (const char* bad :
       {"#lockstep", "#lockstep atten", "#lockstep atten 1 2", "#lockstep atten 1 2 3 4",
        "#lockstep atten -1 0 0", "#lockstep atten 0 0 0", "#lockstep atten 1 nan 0",
        "#lockstep spot 0 0 -1 30", "#lockstep spot 0 0 0 30 1", "#lockstep spot 0 0 -1 0 1",
        "#lockstep spot 0 0 -1 91 1", "#lockstep spot 0 0 -1 30 -2", "#lockstep spot 0 0 inf 30 1",
        "#lockstep glow 1", "#lockstep atten 1 0 0\n#lockstep atten 1 0 0"}) {
    const std::string text = std::string(kView) + "l 1 2 3\n" + bad + "\n";
    try {
      parse_nff(text, "bad.nff");
      ADD_FAILURE() << "accepted: " << bad;
    } catch (const InputError& e) {
      const std::string what = e.what();
      const bool twice = std::string(bad).find('\n') != std::string::npos;
      EXPECT_NE(what.find(twice ? "bad.nff:10:" : "bad.nff:9:"), std::string::npos)
          << bad << " -> " << what;
    }
  }
}

// ---------------------------------------------------------------- closed form

struct Config {
  std::string name;
  Vec3 light;     // position
  Vec3 ip;        // colour
  Vec3 dir;       // spot direction as written (not normalised)
  double cutoff;  // degrees
  double exponent;
  Vec3 c;               // attenuation c1 c2 c3
  bool clamps;          // whether min(1, .) is active somewhere in the image
  Vec3 color{1, 1, 1};  // material
  double kd = 1.0;
};

std::string nff_of(const Config& k) {
  char buf[1024];
  std::snprintf(buf, sizeof buf,
                "%sl %.17g %.17g %.17g %.17g %.17g %.17g\n"
                "#lockstep spot %.17g %.17g %.17g %.17g %.17g\n"
                "#lockstep atten %.17g %.17g %.17g\n"
                "f %.17g %.17g %.17g %.17g 0 1 0 1\n"
                "p 4\n-50 -50 0\n50 -50 0\n50 50 0\n-50 50 0\n",
                kView, k.light.x, k.light.y, k.light.z, k.ip.x, k.ip.y, k.ip.z, k.dir.x, k.dir.y,
                k.dir.z, k.cutoff, k.exponent, k.c.x, k.c.y, k.c.z, k.color.x, k.color.y, k.color.z,
                k.kd);
  return buf;
}

// What the textbook says, with each factor switchable so that the test can
// show that a wrong factor would be caught.
struct Formula {
  bool atten = true, clamp = true, cone = true, falloff = true;
};
Vec3 expected(const Config& k, const Vec3& p, Formula f = {}) {
  const Vec3 kd_c = k.kd * k.color;
  const Vec3 ambient = 0.1 * kd_c;
  const Vec3 to_light = k.light - p;
  const double d =
      std::sqrt(to_light.x * to_light.x + to_light.y * to_light.y + to_light.z * to_light.z);
  const Vec3 l = to_light / d;
  const double n_dot_l = l.z;  // the floor's normal is +z
  if (n_dot_l <= 0) return ambient;
  // Foley 16.1.4.
  double f_att = 1.0 / (k.c.x + k.c.y * d + k.c.z * d * d);
  if (f.clamp) f_att = std::min(1.0, f_att);
  if (!f.atten) f_att = 1.0;
  // Warn: the cosine between -L and the spot's unit direction.
  const Vec3 dir = k.dir / std::sqrt(k.dir.x * k.dir.x + k.dir.y * k.dir.y + k.dir.z * k.dir.z);
  const double cos_a = -(l.x * dir.x + l.y * dir.y + l.z * dir.z);
  const bool inside =
      std::acos(std::clamp(cos_a, -1.0, 1.0)) <= k.cutoff * std::numbers::pi / 180.0;
  double spot = f.falloff ? std::pow(std::max(0.0, cos_a), k.exponent) : 1.0;
  if (f.cone && !inside) spot = 0.0;
  const double s = f_att * spot * n_dot_l;
  return ambient + Vec3{s * k.ip.x * kd_c.x, s * k.ip.y * kd_c.y, s * k.ip.z * kd_c.z};
}

// Exact hit of pixel (i, j)'s centre ray on z = 0.
Vec3 floor_point(const Camera& cam, int i, int j) {
  const Ray r = cam.primary(i, j);
  return r.o + (-r.o.z / r.d.z) * r.d;
}

double max_channel_diff(const Vec3& a, const Vec3& b) {
  return std::max({std::abs(a.x - b.x), std::abs(a.y - b.y), std::abs(a.z - b.z)});
}

// The reference shades in double and stores float: its error is the float
// rounding of the output, at most 2^-24 |value| (measured: 6.0e-8 on a value
// of 1.08), plus a little for the double arithmetic. simd and embree shade in
// float: measured 2.0e-7 .. 7.4e-7 over the three configurations (AVX2, this
// machine); kOptBound leaves under 3x that.
constexpr double kRefRelative = 0x1p-24;
constexpr double kRefSlack = 1e-12;
constexpr double kOptBound = 2e-6;

const Config kConfigs[] = {
    // A narrow spot with a cos^3 falloff and all three attenuation terms.
    {"narrow_cos3", {0, 0, 4}, {1, 1, 1}, {0, 0, -1}, 20, 3, {0.2, 0.1, 0.05}, false},
    // A wide hard-edged cone (exponent 0), pure inverse square: clamped to 1
    // near the light (d < sqrt(10)), 1 / (0.1 d^2) beyond.
    {"wide_inverse_square_clamped", {0, 0, 2}, {1, 1, 1}, {0, 0, -1}, 70, 0, {0, 0, 0.1}, true},
    // A tilted, unnormalised direction, a coloured light on a coloured floor.
    {"tilted_coloured",
     {-1, 0.5, 3},
     {0.8, 0.6, 0.4},
     {1, 0, -2},
     30,
     10,
     {0.5, 0.2, 0},
     false,
     {1, 0.5, 0.25},
     0.9},
};

void PrintTo(const Config& k, std::ostream* os) { *os << k.name << ":\n" << nff_of(k); }

class ClosedForm : public ::testing::TestWithParam<Config> {};

TEST_P(ClosedForm, EveryImplementationMatchesTheFormula) {
  const Config& k = GetParam();
  const Scene scene = parse_nff(nff_of(k), k.name + ".nff");
  FrameOptions opts;
  opts.width = opts.height = 41;
  opts.threads = 1;
  const Camera cam = Camera::from_view(scene.view, opts.width, opts.height);

  // The configuration discriminates: it has lit and unlit pixels, and every
  // wrong variant of the formula is far from the right one somewhere.
  int inside = 0, outside = 0;
  double off_atten = 0, off_clamp = 0, off_cone = 0, off_falloff = 0;
  for (int j = 0; j < opts.height; ++j) {
    for (int i = 0; i < opts.width; ++i) {
      const Vec3 p = floor_point(cam, i, j);
      const Vec3 e = expected(k, p);
      (max_channel_diff(e, 0.1 * k.kd * k.color) > 0 ? inside : outside)++;
      off_atten = std::max(off_atten, max_channel_diff(e, expected(k, p, {.atten = false})));
      off_clamp = std::max(off_clamp, max_channel_diff(e, expected(k, p, {.clamp = false})));
      off_cone = std::max(off_cone, max_channel_diff(e, expected(k, p, {.cone = false})));
      off_falloff = std::max(off_falloff, max_channel_diff(e, expected(k, p, {.falloff = false})));
    }
  }
  EXPECT_GT(inside, 20) << k.name;
  EXPECT_GT(outside, 20) << k.name;
  EXPECT_GT(off_atten, 0.05) << k.name << ": attenuation does not matter in this configuration";
  EXPECT_GT(off_cone, 0.05) << k.name << ": the cone does not matter";
  if (k.exponent > 0) {
    EXPECT_GT(off_falloff, 0.05) << k.name << ": the falloff does not matter";
  }
  if (k.clamps) {
    EXPECT_GT(off_clamp, 0.05) << k.name << ": min(1, .) does not matter";
  }

  struct Impl {
    const char* name;
    std::function<Image(const Scene&, const FrameOptions&, FrameStats*)> render;
    double relative, absolute;  // bound: relative * |value| + absolute
  };
  const Impl impls[] = {{"reference", ref::render, kRefRelative, kRefSlack},
                        {"simd", opt::simd::render, 0, kOptBound},
                        {"embree", opt::embree::render, 0, kOptBound}};
  for (const Impl& im : impls) {
    const Image img = im.render(scene, opts, nullptr);
    double worst = 0, worst_excess = -1;  // largest error; largest error / bound
    int failures = 0;
    for (int j = 0; j < opts.height; ++j) {
      for (int i = 0; i < opts.width; ++i) {
        const Vec3 e = expected(k, floor_point(cam, i, j));
        const float* got = img.pixel(i, j);
        const double err = max_channel_diff(e, Vec3{got[0], got[1], got[2]});
        const double bound = im.relative * std::max({e.x, e.y, e.z}) + im.absolute;
        worst = std::max(worst, err);
        worst_excess = std::max(worst_excess, err / bound);
        if (!(err <= bound) && ++failures <= 5)
          ADD_FAILURE() << k.name << " / " << im.name << ": pixel (" << i << ", " << j << ") rgb "
                        << got[0] << " " << got[1] << " " << got[2] << ", closed form " << e.x
                        << " " << e.y << " " << e.z << ", error " << err << " > bound " << bound;
      }
    }
    EXPECT_EQ(failures, 0) << k.name << " / " << im.name;
    std::printf("[ lights ] %s / %s: max error %.3g (%.2f of the bound)\n", k.name.c_str(), im.name,
                worst, worst_excess);
  }
}

INSTANTIATE_TEST_SUITE_P(NffLights, ClosedForm, ::testing::ValuesIn(kConfigs),
                         [](const auto& info) { return info.param.name; });

// light_at itself: the factors multiply the colour, and an ordinary light is untouched.
TEST(NffLights, LightAtScalesTheIntensity) {
  Scene s;
  Light l;
  l.position = {0, 0, 4};
  l.color = {1, 1, 1};
  l.has_color = true;
  s.lights.push_back(l);
  const Vec3 p{0, 0, 0};
  EXPECT_EQ(light_at(s, l, p).ip, (Vec3{1, 1, 1}));
  l.atten = {0, 0.5, 0};  // 1 / (0.5 * 4)
  EXPECT_DOUBLE_EQ(light_at(s, l, p).ip.x, 0.5);
  l.spot = true;
  l.spot_dir = normalize(Vec3{1, 0, -1});  // 45 degrees off the line to p
  l.spot_cutoff = 44.9;
  EXPECT_EQ(light_at(s, l, p).ip.x, 0.0);
  l.spot_cutoff = 45.1;
  l.spot_exponent = 2;  // cos^2 45 = 1/2
  EXPECT_NEAR(light_at(s, l, p).ip.x, 0.25, 1e-15);
}

}  // namespace
}  // namespace lockstep

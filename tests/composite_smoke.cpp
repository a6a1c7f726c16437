// Smoke tests of the compositing family's library code: exact 8-bit rounding,
// opt::simd and opt::oiio against the reference on synthetic stacks, the tiling
// helper, and the stack reader's errors. (The property tests live in props/.)
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <atomic>
#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include "core/error.h"
#include "io/layers.h"
#include "optimized/composite_simd.h"
#include "optimized/composite_oiio.h"
#include "optimized/tiling.h"
#include "registry/registry.h"
#include "reference/composite.h"
#include "reference/synthetic_stack.h"
#include "io/image_io.h"

namespace lockstep {
namespace {

namespace fs = std::filesystem;

// ---------------------------------------------------------------- 8-bit arithmetic

TEST(CompositeSmoke, Mul255IsExactForAll65536Pairs) {
  for (int x = 0; x < 256; ++x) {
    for (int a = 0; a < 256; ++a) {
      // round(x a / 255): x a / 255 is never exactly k + 1/2 (255 is odd), so
      // floor((2 x a + 255) / 510) is the rounded value.
      const int exact = (2 * x * a + 255) / 510;
      ASSERT_EQ(int(ref::mul255(uint8_t(x), uint8_t(a))), exact) << "x=" << x << " a=" << a;
    }
  }
}

// The same exhaustively through opt::simd's 16-bit lanes: premultiplying a
// straight layer whose pixel (x, a) is (x, 255 - x, x, a) computes mul255 for
// every pair; a transparent-black front of alpha a over an opaque back of
// colour x computes x (255 - a) / 255 for every pair.
TEST(CompositeSmoke, SimdMul255IsExactForAll65536Pairs) {
  LayerStack one, two;
  one.storage = two.storage = Storage::unorm8;
  Layer straight;
  straight.alpha = Alpha::straight;
  straight.image.width = straight.image.height = 256;  // the float pixels are ignored with unorm8
  straight.rgba8.resize(256 * 256 * 4);
  Layer front = straight, back = straight;
  front.alpha = back.alpha = Alpha::premultiplied;
  for (int a = 0; a < 256; ++a)
    for (int x = 0; x < 256; ++x) {
      uint8_t* p = &straight.rgba8[size_t(a * 256 + x) * 4];
      p[0] = uint8_t(x), p[1] = uint8_t(255 - x), p[2] = uint8_t(x), p[3] = uint8_t(a);
      uint8_t* f = &front.rgba8[size_t(a * 256 + x) * 4];
      f[0] = f[1] = f[2] = 0, f[3] = uint8_t(a);
      uint8_t* b = &back.rgba8[size_t(a * 256 + x) * 4];
      b[0] = b[1] = b[2] = uint8_t(x), b[3] = 255;
    }
  one.layers = {straight};
  two.layers = {front, back};
  const Image p = opt::simd::composite(one, {}, nullptr);
  const Image o = opt::simd::composite(two, {}, nullptr);
  for (int a = 0; a < 256; ++a)
    for (int x = 0; x < 256; ++x) {
      const float* pp = p.pixel(x, a);
      const float* op = o.pixel(x, a);
      ASSERT_EQ(pp[0], float((2 * x * a + 255) / 510) / 255.0f) << "x=" << x << " a=" << a;
      ASSERT_EQ(pp[1], float((2 * (255 - x) * a + 255) / 510) / 255.0f) << "x=" << x << " a=" << a;
      ASSERT_EQ(op[0], float((2 * x * (255 - a) + 255) / 510) / 255.0f) << "x=" << x << " a=" << a;
    }
}

TEST(CompositeSmoke, EightBitHelpers) {
  EXPECT_EQ(ref::premultiply8({255, 128, 0, 128}).r, 128);
  EXPECT_EQ(ref::premultiply8({255, 128, 0, 128}).g, 64);  // 128 * 128 / 255 = 64.25
  const Rgba8 o = ref::over_premultiplied8({100, 0, 0, 255}, {50, 50, 50, 255});
  EXPECT_EQ(o.r, 100);
  EXPECT_EQ(o.g, 0);
  EXPECT_EQ(o.a, 255);
  EXPECT_EQ(ref::unpremultiply8({0, 0, 0, 0}).r, 0);
  EXPECT_EQ(ref::unpremultiply8({64, 0, 0, 128}).r, 128);  // round(64 * 255 / 128) = 127.5 -> 128
  // A colour brighter than its alpha saturates instead of wrapping.
  EXPECT_EQ(ref::over_premultiplied8({200, 0, 0, 100}, {255, 0, 0, 255}).r, 255);
}

TEST(CompositeSmoke, StraightOverNeverMakesNaN) {
  const Rgba o = ref::over_straight({0.5f, 0.5f, 0.5f, 0}, {0.25f, 0.25f, 0.25f, 0});
  EXPECT_EQ(o.r, ref::kStraightClear.r);
  EXPECT_EQ(o.a, 0.0f);
  const Rgba u = ref::unpremultiply({0, 0, 0, 0});
  EXPECT_FALSE(std::isnan(u.r));
  // Straight and premultiplied over agree on ordinary values.
  const Rgba f{0.8f, 0.4f, 0.2f, 0.3f}, b{0.1f, 0.9f, 0.5f, 0.6f};
  const Rgba s = ref::premultiply(ref::over_straight(f, b));
  const Rgba p = ref::over_premultiplied(ref::premultiply(f), ref::premultiply(b));
  EXPECT_NEAR(s.r, p.r, 1e-6);
  EXPECT_NEAR(s.g, p.g, 1e-6);
  EXPECT_NEAR(s.a, p.a, 1e-7);
}

// ---------------------------------------------------------------- implementations vs reference

struct Diff {
  double max_abs = 0;
  uint32_t max_ulps = 0;
  double max_levels = 0;  // max_abs in units of 1/255
};

uint32_t ulps(float a, float b) {
  if (a == b) return 0;
  if (std::isnan(a) || std::isnan(b)) return std::numeric_limits<uint32_t>::max();
  // Both >= 0 here (every value is a composite of values >= 0).
  const int64_t ia = std::bit_cast<int32_t>(a), ib = std::bit_cast<int32_t>(b);
  return uint32_t(std::min<int64_t>(std::llabs(ia - ib), std::numeric_limits<uint32_t>::max()));
}

Diff compare(const Image& a, const Image& b) {
  Diff d;
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  EXPECT_EQ(a.rgba.size(), b.rgba.size());
  for (size_t i = 0; i < std::min(a.rgba.size(), b.rgba.size()); ++i) {
    d.max_abs = std::max(d.max_abs, double(std::fabs(a.rgba[i] - b.rgba[i])));
    d.max_ulps = std::max(d.max_ulps, ulps(a.rgba[i], b.rgba[i]));
    EXPECT_FALSE(std::isnan(a.rgba[i])) << i;
  }
  d.max_levels = d.max_abs * 255.0;
  return d;
}

struct Case {
  Storage storage;
  Order order;
  Alpha alpha;
  bool early_stop;
};

std::string name(const Case& c) {
  return std::string(name_of(c.storage)) + "/" + name_of(c.order) + "/" + name_of(c.alpha) +
         (c.early_stop ? "/early-stop" : "/no-stop");
}

class Agreement : public ::testing::TestWithParam<Case> {};

TEST_P(Agreement, SimdAndOiioMatchTheReference) {
  const Case c = GetParam();
  // Odd sizes: vector tails, chunk and band remainders. 6 layers, opaque from
  // index 2 on (early termination happens), and one with a single layer.
  for (const auto& [w, h, n, opaque_from, seed] :
       std::vector<std::tuple<int, int, int, int, uint64_t>>{{67, 45, 6, 2, 1},
                                                             {1, 1, 3, -1, 2},
                                                             {300, 7, 2, 0, 3},
                                                             {33, 40, 1, -1, 4},
                                                             {129, 70, 9, 4, 5},
                                                             {256, 128, 16, -1, 6}}) {
    LayerStack s = synthetic_stack(w, h, n, opaque_from, c.alpha, c.storage, seed);
    s.order = c.order;
    s.early_stop = c.early_stop;
    FrameOptions o;
    o.threads = 2;
    FrameStats rs, ss, os;
    const Image r = ref::composite(s, o, &rs);
    const Image simd = opt::simd::composite(s, o, &ss);
    const Image oiio = opt::oiio::composite(s, o, &os);
    EXPECT_EQ(rs.items, uint64_t(w) * uint64_t(h));
    EXPECT_EQ(ss.items, rs.items);
    EXPECT_EQ(os.items, rs.items);
    const Diff ds = compare(simd, r), dox = compare(oiio, r);
    std::printf(
        "  %-40s %3dx%-3d %d layers  simd: %u ulps (%.3g abs, %.3g levels)  oiio: %u ulps (%.3g "
        "abs, %.3g levels)\n",
        name(c).c_str(), w, h, n, ds.max_ulps, ds.max_abs, ds.max_levels, dox.max_ulps, dox.max_abs,
        dox.max_levels);
    if (c.storage == Storage::unorm8) {
      EXPECT_EQ(ds.max_abs, 0.0) << "simd 8-bit must equal the reference exactly";
      EXPECT_LE(dox.max_levels, 1.0 + 1e-6) << "oiio 8-bit within 1 level";
    } else if (c.alpha == Alpha::premultiplied) {
      EXPECT_EQ(ds.max_ulps, 0u) << "simd premultiplied float is bit-identical to the reference";
      EXPECT_LE(dox.max_abs, 1e-6);
    } else {
      // Straight layers: the reference uses the straight formula, simd
      // premultiplies first.
      EXPECT_LE(ds.max_abs, 1e-6);
      EXPECT_LE(dox.max_abs, 1e-6);
    }
  }
}

std::vector<Case> all_cases() {
  std::vector<Case> v;
  for (Storage s : {Storage::f32, Storage::unorm8})
    for (Order o : {Order::front_to_back, Order::back_to_front})
      for (Alpha a : {Alpha::straight, Alpha::premultiplied})
        for (bool e : {true, false}) v.push_back({s, o, a, e});
  return v;
}

INSTANTIATE_TEST_SUITE_P(CompositeSmoke, Agreement, ::testing::ValuesIn(all_cases()),
                         [](const ::testing::TestParamInfo<Case>& i) {
                           std::string n = name(i.param);
                           for (char& ch : n)
                             if (ch == '/' || ch == '-') ch = '_';
                           return n;
                         });

// Every Highway target compiled in and supported here (AVX2, AVX-512, ...):
// bit-identical to the reference on premultiplied float and on 8 bits.
TEST(CompositeSmoke, EveryHighwayTargetMatchesTheReference) {
  for (const int64_t t : hwy::SupportedAndGeneratedTargets()) {
    hwy::SetSupportedTargetsForTest(t);
    EXPECT_EQ(std::string(opt::simd::composite_target_name()), std::string(hwy::TargetName(t)));
    for (Storage st : {Storage::f32, Storage::unorm8})
      for (Alpha a : {Alpha::straight, Alpha::premultiplied}) {
        const LayerStack s = synthetic_stack(77, 23, 5, 2, a, st, 7);
        const Diff d =
            compare(opt::simd::composite(s, {}, nullptr), ref::composite(s, {}, nullptr));
        std::printf("  %-8s %-6s %-13s %u ulps\n", hwy::TargetName(t), name_of(st), name_of(a),
                    d.max_ulps);
        if (st == Storage::unorm8 || a == Alpha::premultiplied) {
          EXPECT_EQ(d.max_ulps, 0u) << hwy::TargetName(t);
        } else {
          EXPECT_LE(d.max_abs, 1e-6) << hwy::TargetName(t);
        }
      }
  }
  hwy::SetSupportedTargetsForTest(0);  // back to the real CPU
}

TEST(CompositeSmoke, EdgeAlphasAgree) {
  // Alpha exactly 0 and 1, tiny alphas and a colour over an empty pixel.
  LayerStack s;
  s.source = "edges";
  const float alphas[] = {0.0f, 1.0f, 1e-30f, 1e-7f, 0.5f, std::nextafter(1.0f, 0.0f)};
  for (int l = 0; l < 3; ++l) {
    Layer layer;
    layer.alpha = l == 1 ? Alpha::premultiplied : Alpha::straight;
    layer.image = Image(6, 6);
    for (int y = 0; y < 6; ++y)
      for (int x = 0; x < 6; ++x) {
        const float a = alphas[(x + l * y) % 6];
        const float c = 0.25f + 0.1f * float((x * 3 + y + l) % 7);
        float* p = layer.image.pixel(x, y);
        p[0] = layer.alpha == Alpha::premultiplied ? c * a : c;
        p[1] = p[0] * 0.5f;
        p[2] = 0;
        p[3] = a;
      }
    s.layers.push_back(layer);
  }
  for (Order o : {Order::front_to_back, Order::back_to_front}) {
    s.order = o;
    const Image r = ref::composite(s, {}, nullptr);
    const Diff d = compare(opt::simd::composite(s, {}, nullptr), r);
    EXPECT_LE(d.max_abs, 1e-6) << name_of(o);
    LayerStack s8 = s;
    to_unorm8(s8);
    EXPECT_EQ(
        compare(opt::simd::composite(s8, {}, nullptr), ref::composite(s8, {}, nullptr)).max_abs,
        0.0);
  }
}

TEST(CompositeSmoke, EarlyStopChangesNothing) {
  LayerStack s = synthetic_stack(97, 31, 8, 1, Alpha::premultiplied, Storage::f32, 9);
  const Image a = ref::composite(s, {}, nullptr);
  s.early_stop = false;
  const Image b = ref::composite(s, {}, nullptr);
  EXPECT_EQ(compare(a, b).max_ulps, 0u);
}

// The simd row's session (registry/composite_row.cpp: its frame buffer kept across
// frames): every frame equals run's, the buffer is reused once the caller has
// dropped the last frame, and a frame the caller still holds is never written.
TEST(CompositeSmoke, SessionKeepsItsBufferAndNeverOverwritesAHeldFrame) {
  const Family* fam = registry().find("composite");
  ASSERT_NE(fam, nullptr);
  const FamilyImpl* simd = fam->find("simd");
  ASSERT_NE(simd, nullptr);
  ASSERT_TRUE(simd->session);
  auto input = [](int seed) {
    return make_input<LayerStack>(
        synthetic_stack(67, 41, 3, -1, Alpha::premultiplied, Storage::f32, seed), "s", 67, 41);
  };
  const Input a = input(3), b = input(4);
  const FrameOptions o;
  RunResources resources;
  const auto run = simd->session(a, o, resources);
  const float* kept = nullptr;
  {
    const Output fa = run(a, o, nullptr);
    kept = output_as<Image>(fa).rgba.data();
    EXPECT_EQ(compare(output_as<Image>(fa), simd->run_as<Image>(a, o, nullptr)).max_ulps, 0u);
    // Held: the next frame goes elsewhere, and this one is unchanged.
    const Output fb = run(b, o, nullptr);
    EXPECT_NE(output_as<Image>(fb).rgba.data(), kept);
    EXPECT_EQ(compare(output_as<Image>(fa), simd->run_as<Image>(a, o, nullptr)).max_ulps, 0u);
    EXPECT_EQ(compare(output_as<Image>(fb), simd->run_as<Image>(b, o, nullptr)).max_ulps, 0u);
    kept = output_as<Image>(fb).rgba.data();
  }
  // Both dropped: the session's buffer (the last one) is written again.
  {
    const Output fc = run(a, o, nullptr);
    EXPECT_EQ(output_as<Image>(fc).rgba.data(), kept);
    EXPECT_EQ(compare(output_as<Image>(fc), simd->run_as<Image>(a, o, nullptr)).max_ulps, 0u);
  }
  // Taken by the caller (take_output) while the session holds it: a copy.
  Image taken = take_output<Image>(run(b, o, nullptr));
  EXPECT_NE(taken.rgba.data(), kept);
  EXPECT_EQ(compare(taken, simd->run_as<Image>(b, o, nullptr)).max_ulps, 0u);
}

TEST(CompositeSmoke, BadStacksAreInputErrors) {
  LayerStack empty;
  empty.source = "empty.stack";
  EXPECT_THROW(ref::composite(empty, {}, nullptr), InputError);
  EXPECT_THROW(opt::simd::composite(empty, {}, nullptr), InputError);
  EXPECT_THROW(opt::oiio::composite(empty, {}, nullptr), InputError);
  LayerStack s = synthetic_stack(8, 8, 2, -1, Alpha::straight, Storage::f32, 1);
  s.layers[1].image = Image(8, 9);
  EXPECT_THROW(opt::simd::composite(s, {}, nullptr), InputError);
  LayerStack q = synthetic_stack(8, 8, 2, -1, Alpha::straight, Storage::f32, 1);
  q.storage = Storage::unorm8;  // no rgba8
  EXPECT_THROW(opt::simd::composite(q, {}, nullptr), InputError);
}

TEST(CompositeSmoke, CorpusStacksAgree) {
  int count = 0;
  for (const auto& e : fs::directory_iterator(LOCKSTEP_CORPUS_DIR "/stacks")) {
    if (e.path().extension() != ".stack") continue;
    ++count;
    const LayerStack s = read_stack(e.path().string(), std::nullopt);
    FrameOptions o;
    o.threads = 2;
    const Image r = ref::composite(s, o, nullptr);
    const Diff ds = compare(opt::simd::composite(s, o, nullptr), r);
    const Diff dox = compare(opt::oiio::composite(s, o, nullptr), r);
    std::printf("  %-22s %zu layers %s %s  simd: %u ulps (%.3g abs)  oiio: %u ulps (%.3g abs)\n",
                e.path().filename().c_str(), s.layers.size(), name_of(s.order), name_of(s.storage),
                ds.max_ulps, ds.max_abs, dox.max_ulps, dox.max_abs);
    EXPECT_LE(ds.max_abs, 1e-6) << e.path();
    EXPECT_LE(dox.max_abs, 1e-6) << e.path();
    if (s.storage == Storage::unorm8) {
      EXPECT_EQ(ds.max_abs, 0.0) << e.path();
    }
  }
  EXPECT_GE(count, 5);
}

// ---------------------------------------------------------------- tiling

TEST(CompositeSmoke, ParallelTilesCoverEveryPixelOnceWithMonotoneProgress) {
  const int w = 103, h = 57;
  std::vector<std::atomic<int>> hits(size_t(w) * h);
  std::vector<double> reports;
  std::atomic<int> inside{0};
  bool overlapped = false;
  opt::parallel_tiles(
      w, h, 16, 8, 2,
      [&](double f) {
        if (++inside > 1) overlapped = true;
        reports.push_back(f);
        --inside;
      },
      [&](int x0, int y0, int x1, int y1) {
        for (int y = y0; y < y1; ++y)
          for (int x = x0; x < x1; ++x) ++hits[size_t(y) * w + x];
      });
  for (auto& c : hits) ASSERT_EQ(c.load(), 1);
  EXPECT_FALSE(overlapped);
  ASSERT_FALSE(reports.empty());
  EXPECT_EQ(reports.back(), 1.0);
  for (size_t i = 1; i < reports.size(); ++i) EXPECT_LE(reports[i - 1], reports[i]);
}

// ---------------------------------------------------------------- the reader

class Files : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = fs::temp_directory_path() /
          ("lockstep-composite-smoke-" +
           std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "-" +
           ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  void TearDown() override { fs::remove_all(dir); }

  // Writes an image with `nc` channels of float data (straight for PNG).
  std::string write(const std::string& name, int w, int h, int nc, const std::vector<float>& v) {
    const std::string p = (dir / name).string();
    auto out = OIIO::ImageOutput::create(p);
    EXPECT_TRUE(out);
    OIIO::ImageSpec spec(w, h, nc,
                         name.ends_with(".png") ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT);
    if (nc == 4) spec.alpha_channel = 3;
    spec.attribute("oiio:UnassociatedAlpha", 1);
    EXPECT_TRUE(out->open(p, spec));
    EXPECT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, v.data()));
    out->close();
    return p;
  }
  std::string rgba(const std::string& name, int w, int h, float r, float a) {
    std::vector<float> v(size_t(w) * h * 4);
    for (size_t i = 0; i < v.size(); i += 4) v[i] = r, v[i + 1] = r, v[i + 2] = r, v[i + 3] = a;
    return write(name, w, h, 4, v);
  }
  std::string text(const std::string& name, const std::string& body) {
    const std::string p = (dir / name).string();
    std::ofstream(p) << body;
    return p;
  }
  // The InputError message of read_stack(path), or "" when it does not throw.
  static std::string error_of(const std::string& path) {
    try {
      read_stack(path, std::nullopt);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
  fs::path dir;
};

TEST_F(Files, PngIsReadStraightAndExrPremultiplied) {
  rgba("a.png", 4, 3, 200.0f / 255.0f, 128.0f / 255.0f);
  rgba("b.exr", 4, 3, 0.25f, 0.5f);
  const LayerStack s = read_stack(text("s.stack", "# two layers\na.png\nb.exr\n"), std::nullopt);
  ASSERT_EQ(s.layers.size(), 2u);
  EXPECT_EQ(s.layers[0].alpha, Alpha::straight);
  EXPECT_EQ(s.layers[1].alpha, Alpha::premultiplied);
  // Not premultiplied by OIIO on the way in: 200/255 stays 200/255.
  EXPECT_EQ(s.layers[0].image.rgba[0], 200.0f / 255.0f);
  EXPECT_EQ(s.layers[0].image.rgba[3], 128.0f / 255.0f);
  EXPECT_EQ(s.layers[1].image.rgba[0], 0.25f);
  EXPECT_EQ(s.width(), 4);
  const LayerStack o =
      read_stack(text("o.stack", "alpha premultiplied\norder btf\nstorage unorm8\na.png\nb.exr\n"),
                 std::nullopt);
  EXPECT_EQ(o.layers[0].alpha, Alpha::premultiplied);
  EXPECT_EQ(o.order, Order::back_to_front);
  EXPECT_EQ(o.storage, Storage::unorm8);
  EXPECT_EQ(o.layers[0].rgba8[0], 200);
  EXPECT_EQ(o.layers[0].rgba8[3], 128);
  // The caller's override wins over the file's line.
  EXPECT_EQ(
      read_stack(text("p.stack", "alpha premultiplied\na.png\n"), Alpha::straight).layers[0].alpha,
      Alpha::straight);
}

TEST_F(Files, ReadErrorsNameTheFileAndLine) {
  rgba("ok.png", 4, 3, 0.5f, 0.5f);
  rgba("big.png", 5, 3, 0.5f, 0.5f);
  write("rgb.png", 4, 3, 3, std::vector<float>(36, 0.5f));
  std::vector<float> nan(48, 0.5f);
  nan[(1 * 4 + 2) * 4 + 1] = std::numeric_limits<float>::quiet_NaN();  // pixel (2, 1), G
  write("nan.exr", 4, 3, 4, nan);
  std::vector<float> neg(48, 0.5f);
  neg[(2 * 4 + 3) * 4 + 3] = -0.25f;  // pixel (3, 2), A
  write("neg.exr", 4, 3, 4, neg);
  // A truncated PNG: the first half of a valid one.
  {
    std::vector<float> v(64 * 64 * 4);
    for (size_t i = 0; i < v.size(); ++i) v[i] = float((i * 7919) % 256) / 255.0f;
    const std::string p = write("full.png", 64, 64, 4, v);
    std::ifstream in(p, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), {});
    std::ofstream((dir / "trunc.png").string(), std::ios::binary)
        << bytes.substr(0, bytes.size() / 2);
  }

  auto expect = [&](const std::string& body, const std::string& line_prefix,
                    const std::string& what) {
    const std::string p = text("t.stack", body);
    const std::string e = error_of(p);
    std::printf("  %s\n", e.substr(dir.string().size() + 1).c_str());
    EXPECT_NE(e.find(p + line_prefix), std::string::npos) << "message: " << e;
    EXPECT_NE(e.find(what), std::string::npos) << "message: " << e << "\nexpected: " << what;
  };
  expect("ok.png\nrgb.png\n",
         ":2: ", "has no alpha channel (3 channels: R,G,B); lockstep composite needs RGBA");
  expect("nan.exr\n", ":1: ", "pixel (2, 1) channel G is NaN");
  expect("# negative\nneg.exr\n", ":2: ", "pixel (3, 2) channel A is negative");
  expect("ok.png\nbig.png\n", ":2: ", "is 5x3 but layer");
  expect("ok.png\nbig.png\n", ":2: ", "ok.png' is 4x3");
  expect("# nothing\n\n", ": ", "stack has no layers");
  expect("ok.png\nblend multiply\n", ":2: ", "unknown keyword 'blend'");
  expect("ok.png\nfrobnicate\n", ":2: ", "unknown keyword 'frobnicate'");
  expect("ok.png\nnot-there.png\n", ":2: ", "not-there.png: cannot read layer: no such file");
  expect("trunc.png\n", ":1: ", "trunc.png: cannot read layer");
  std::ofstream((dir / "empty.png").string()) << "";
  std::ofstream((dir / "garbage.exr").string()) << "this is not an EXR file";
  expect("empty.png\n", ":1: ", "empty.png: cannot read layer");
  expect("garbage.exr\n", ":1: ", "garbage.exr: cannot read layer");
  fs::create_directories(dir / "adir.png");
  expect("adir.png\n", ":1: ", "adir.png: cannot read layer: is a directory");
  expect("order sideways\nok.png\n", ":1: ", "order must be 'ftb' or 'btf'");
  expect("alpha maybe\nok.png\n", ":1: ", "alpha must be");
  expect("storage half\nok.png\n", ":1: ", "storage must be");
  EXPECT_NE(error_of((dir / "nope.stack").string()).find("no such file"), std::string::npos);
  // read_layers names the layer file itself.
  try {
    read_layers({(dir / "ok.png").string(), (dir / "rgb.png").string()}, std::nullopt);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("rgb.png: has no alpha channel"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(read_layers({}, std::nullopt), InputError);
}

}  // namespace
}  // namespace lockstep

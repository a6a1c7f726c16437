// lockstep texture failure maps (issue #32): where each filter breaks, against
// the viewing angle and the texture's frequency, judged by the pixel's exact
// box filter (props/texture/oracle.h).
//
// The scene: a checkerboard (64^2 texels, 8 x 8 checks: 1/16 cycle a texel)
// on a large plane, a 48 x 48 camera (45 degrees) looking at the plane's
// centre from distance 10 at elevation theta (90: straight down; 5: grazing).
// The tiling is chosen so that a pixel at the centre covers m texels across
// (the minification: m > 8 puts more than half a cycle of the checks in a
// pixel, past Nyquist). For every (theta, m) and filter: the RMS error of the
// reference over the interior pixels.
//
// Pixels whose footprint's bounding box holds more than 20,000 texels are
// left out (stderr says how many): the oracle clips every texel of it.
// CSV on stdout: filter,theta,minification,rms. bench/scripts/texture_map_chart.py
// draws one map per filter and states, per angle, the largest minification
// each filter holds under RMS 0.05 (the boundary). Claims (--quick, a ctest):
// point sampling breaks past Nyquist straight down (RMS > 0.2 at m = 16; at
// m = 1 less than half of that: its error there is the checks' edges, where
// a pixel straddles two texels); trilinear holds straight down but breaks
// at grazing angles where anisotropic filtering holds (RMS at theta = 10,
// m = 4: aniso16 less than half of trilinear's).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "bench/studies/study.h"
#include "io/texture_scene.h"
#include "props/texture/oracle.h"
#include "registry/registry.h"

using namespace lockstep;

namespace {

TextureScene scene_at(double theta_deg, double minification) {
  TextureScene s;
  s.texture = procedural_texture("checker 64 8", "map", 0);
  const double L = 2000;
  s.origin = {-L / 2, 0, -L / 2};
  s.edge_s = {L, 0, 0};
  s.edge_t = {0, 0, L};
  const double D = 10, th = theta_deg * M_PI / 180;
  s.view.from = {0, D * std::sin(th), D * std::cos(th)};
  s.view.at = {0, 0, 0};
  s.view.up = theta_deg >= 89.999 ? Vec3{0, 0, -1} : Vec3{0, 1, 0};
  s.view.angle = 45;
  s.view.hither = 1e-3;
  s.width = s.height = 48;
  // A pixel at the centre spans D * pitch units across (perpendicular to the
  // view; along the plane's minor axis): m texels, with 64 r / L texels a unit.
  const double pitch = 2 * std::tan(22.5 * M_PI / 180) / 47;
  const double r = minification * L / (D * pitch * 64);
  s.repeat_u = s.repeat_v = r;
  s.background = {0.5, 0.5, 0.5};
  s.source = "checker-plane";
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  if (!study::parse_flags(argc, argv, {{"--quick", &quick}}, "lockstep_texture_map_study [--quick]")) return 2;
  study::Claims claims{"lockstep_texture_map_study"};
  const Family* fam = registry().find("texture");
  if (!fam) return 3;
  const FamilyImpl& ref = fam->reference();
  // --quick: the three cells the claims need.
  std::vector<std::pair<double, double>> cells;
  if (quick) {
    cells = {{90, 1}, {90, 16}, {10, 4}};
  } else {
    for (double th : {5, 10, 20, 30, 45, 60, 90})
      for (double m : {0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0}) cells.push_back({th, m});
  }
  const char* filters[] = {"point", "super4", "trilinear", "aniso4", "aniso16", "ewa"};
  std::map<std::string, double> rms_at;
  std::printf("filter,theta,minification,rms\n");
  for (const auto& [th, m] : cells) {
      const TextureScene sc = scene_at(th, m);
      const TexelMap map = TexelMap::make(sc, sc.width, sc.height);
      std::vector<props::texture::BoxValue> box(size_t(sc.width) * sc.height);
      // Pixels whose footprint's bounding box holds more than kMaxTexels
      // texels are not judged (the oracle clips every one: near the horizon
      // of a grazing view, millions).
      constexpr double kMaxTexels = 20000;
      long unjudged = 0;
      for (int y = 0; y < sc.height; ++y)
        for (int x = 0; x < sc.width; ++x) {
          double lo_a = 1e300, hi_a = -1e300, lo_b = 1e300, hi_b = -1e300;
          bool seen = true;
          for (int k = 0; k < 4; ++k) {
            double a, b;
            if (!map.texel_at(x + (k & 1), y + (k >> 1), a, b)) {
              seen = false;
              break;
            }
            lo_a = std::min(lo_a, a), hi_a = std::max(hi_a, a), lo_b = std::min(lo_b, b), hi_b = std::max(hi_b, b);
          }
          if (!seen || (hi_a - lo_a + 1) * (hi_b - lo_b + 1) > kMaxTexels) {
            unjudged += seen;
            continue;  // box stays not interior
          }
          box[size_t(y) * sc.width + x] = props::texture::pixel_box_filter(sc, map, x, y);
        }
      if (unjudged) std::fprintf(stderr, "theta %g, m %g: %ld pixels over %g texels not judged\n", th, m, unjudged, kMaxTexels);
      const Input in = make_input<TextureScene>(sc, sc.source, sc.width, sc.height, sc.background);
      for (const char* filter : filters) {
        FrameOptions o;
        o.width = sc.width;
        o.height = sc.height;
        o.threads = 1;
        o.params.set("filter", filter);
        FrameStats st;
        const Image img = ref.run_as<Image>(in, o, &st);
        double sq = 0;
        long n = 0;
        for (int y = 0; y < sc.height; ++y)
          for (int x = 0; x < sc.width; ++x) {
            const auto& b = box[size_t(y) * sc.width + x];
            if (!b.interior) continue;
            for (int c = 0; c < 3; ++c) {
              const double d = img.pixel(x, y)[c] - b.rgba[size_t(c)];
              sq += d * d / 3;
            }
            ++n;
          }
        const double rms = n ? std::sqrt(sq / double(n)) : 0;
        rms_at[std::string(filter) + "/" + std::to_string(int(th)) + "/" + std::to_string(m)] = rms;
        std::printf("%s,%g,%g,%.6g\n", filter, th, m, rms);
        std::fflush(stdout);
      }
    }
  auto at = [&](const char* f, int th, double m) { return rms_at[std::string(f) + "/" + std::to_string(th) + "/" + std::to_string(m)]; };
  claims.check(at("point", 90, 16) > 0.2, "point sampling breaks past Nyquist straight down (RMS > 0.2 at m = 16)");
  claims.check(at("point", 90, 1) < 0.5 * at("point", 90, 16),
               "point sampling straight down: RMS at one texel a pixel less than half of that at 16");
  claims.check(at("trilinear", 90, 16) < 0.05, "trilinear holds straight down at m = 16 (RMS < 0.05)");
  claims.check(at("aniso16", 10, 4) < 0.5 * at("trilinear", 10, 4),
               "at 10 degrees and m = 4, aniso16's RMS is less than half of trilinear's");
  return claims.exit_code();
}

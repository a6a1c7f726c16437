// lockstep props: fuzzing the NFF reader.
//
// Property: parse_nff either returns a consistent Scene or throws
// lockstep::InputError -- never another exception, never a crash (built under
// AddressSanitizer + UBSan by scripts/fuzz.sh, any memory error or undefined
// behaviour aborts the run). Inputs: random bytes, random token soups from the
// NFF vocabulary (lockstep's #lockstep light extension included) with hostile
// numbers, and SPD files (props/data; spotlights.nff carries the extension) mutated by
// byte flips, insertions, deletions, duplications, number swaps, line
// insertions and truncation.
//
// Cases: 50x every property's count (parsing is cheap: 5000 cases take well under
// a second, a few seconds under the sanitizers); LOCKSTEP_DEEP=1 makes that 50000.
// Seeds fixed per property, as every property binary's (props/driver/rc_run.h);
// scripts/fuzz.sh draws random ones.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <rapidcheck.h>

#include "core/error.h"
#include "props/driver/rc_run.h"
#include "io/nff.h"

namespace {

using lockstep::InputError;
using lockstep::Scene;

std::string escaped(const std::string& s) {
  std::string out;
  for (unsigned char ch : s) {
    if (ch == '\n') out += "\\n\n";
    else if (ch == '\\') out += "\\\\";
    else if (ch >= 32 && ch < 127) out += char(ch);
    else {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", ch);
      out += buf;
    }
  }
  return out;
}

// What a parsed scene must satisfy.
std::string inconsistency(const Scene& s) {
  if (s.poly_first.size() != s.polygon_count() + 1) return "poly_first size";
  if (s.poly_first.back() != s.vertex.size()) return "poly_first end";
  if (s.vertex_normal.size() != s.vertex.size()) return "vertex_normal size";
  if (s.poly_tri_first.size() != s.polygon_count() + 1) return "poly_tri_first size";
  if (s.poly_tri_first.back() != s.triangle_count()) return "poly_tri_first end";
  if (s.tri_poly.size() != s.triangle_count()) return "tri_poly size";
  for (const auto& t : s.tri_vertex)
    for (uint32_t v : t)
      if (v >= s.vertex.size()) return "triangle vertex out of range";
  for (uint32_t m : s.sphere_material)
    if (m >= s.materials.size()) return "sphere material out of range";
  for (uint32_t m : s.poly_material)
    if (m >= s.materials.size()) return "polygon material out of range";
  for (double r : s.sphere_radius)
    if (!std::isfinite(r) || r == 0) return "bad radius";
  for (const auto& p : s.poly_plane)
    if (!std::isfinite(p.n.x) || !std::isfinite(p.n.y) || !std::isfinite(p.n.z) || !std::isfinite(p.d))
      return "non-finite plane";
  const size_t nc = s.cone_base.size();  // cones (io/nff.cpp read_cone)
  if (s.cone_apex.size() != nc || s.cone_r0.size() != nc || s.cone_r1.size() != nc || s.cone_inside.size() != nc ||
      s.cone_material.size() != nc)
    return "cone array sizes";
  for (size_t i = 0; i < nc; ++i) {
    if (s.cone_material[i] >= s.materials.size()) return "cone material out of range";
    const double r0 = s.cone_r0[i], r1 = s.cone_r1[i];
    if (!(r0 >= 0 && r1 >= 0 && std::isfinite(r0) && std::isfinite(r1)) || (r0 == 0 && r1 == 0)) return "bad cone radii";
    const double h = lockstep::length(s.cone_apex[i] - s.cone_base[i]);
    if (!(h > 0 && std::isfinite(h))) return "bad cone axis";
  }
  for (const auto& l : s.lights) {  // the light extension (io/nff.h)
    if (!(l.atten.x >= 0 && l.atten.y >= 0 && l.atten.z >= 0) || l.atten == lockstep::Vec3{0, 0, 0} ||
        !std::isfinite(l.atten.x + l.atten.y + l.atten.z))
      return "bad attenuation";
    if (!(std::abs(lockstep::length(l.spot_dir) - 1) < 1e-12)) return "spot direction not unit";
    if (!(l.spot_cutoff > 0 && l.spot_cutoff <= 90)) return "spot cutoff";
    if (!(l.spot_exponent >= 0 && std::isfinite(l.spot_exponent))) return "spot exponent";
  }
  if (s.view.xres < 1 || s.view.yres < 1 || s.view.xres > lockstep::kMaxResolution ||
      s.view.yres > lockstep::kMaxResolution)
    return "resolution";
  return "";
}

// Parses; fails the property on anything but a Scene or an InputError.
void parse_ok(const std::string& text) {
  try {
    const Scene s = lockstep::parse_nff(text, "fuzz.nff");
    const std::string bad = inconsistency(s);
    if (!bad.empty()) RC_FAIL("parse_nff returned an inconsistent scene (" + bad + ") for:\n" + escaped(text));
    RC_TAG("parsed");
  } catch (const InputError& e) {
    RC_TAG("InputError");
  } catch (const std::exception& e) {
    RC_FAIL(std::string("parse_nff threw ") + typeid(e).name() + " (" + e.what() + ") instead of InputError for:\n" +
            escaped(text));
  } catch (...) {
    RC_FAIL("parse_nff threw a non-std exception for:\n" + escaped(text));
  }
}

std::vector<std::string> seeds() {
  std::vector<std::string> out;
  for (const auto& e : std::filesystem::directory_iterator(LOCKSTEP_FUZZ_DATA_DIR)) {
    if (e.path().extension() != ".nff") continue;
    std::ifstream f(e.path(), std::ios::binary);
    std::ostringstream ss;
    ss << f.rdbuf();
    out.push_back(ss.str());
  }
  std::sort(out.begin(), out.end());
  return out;
}

const std::vector<std::string> kWords = {
    "v", "b", "l", "f", "s", "p", "pp", "c", "from", "at", "up", "angle", "hither", "resolution", "#", "x",
    "#lockstep", "#lockstep", "atten", "spot", "\n#lockstep atten", "\n#lockstep spot"};
const std::vector<std::string> kNumbers = {
    "0", "1", "-1", "3", "0.5", "1e-300", "1e308", "1.8e308", "-1e400", "1e-400", "nan", "inf", "-inf", "NaN",
    "0x1p-1074", "0x1.fffffffffffffp+1023", "4e-324", "-0", "+1", "1.", ".5", "1e", "--1", "1e+", "0x", "2147483648",
    "-2147483649", "9223372036854775808", "99999999999999999999", "16384", "16385", "1048576", "1048577", "-3", "2",
    "179", "180", "1e-9", "0.001", "1,2", "١"};

rc::Gen<std::string> token() {
  return rc::gen::oneOf(rc::gen::elementOf(kWords), rc::gen::elementOf(kNumbers),
                        rc::gen::map(rc::gen::inRange(-1000000, 1000000), [](int k) { return std::to_string(k); }));
}

rc::Gen<std::string> separator() {
  return rc::gen::elementOf(std::vector<std::string>{" ", " ", " ", "\n", "\n", "\t", "\r\n", "  ", "\n#c\n", "\v", "\f"});
}

// Mutations of a seed file.
const std::vector<std::string> kPlausible = {"0", "1", "-1", "0.5", "-2.25", "3", "4", "12", "1e3", "1e-3", "0x1p-3",
                                            "-0.0001", "255", "90", "100000", "7", "0.999999"};

std::string mutate(std::string s) {
  int n = 1;  // mostly one or two mutations, so that the parser gets deep into the file
  while (n < 8 && *rc::gen::inRange(0, 3) == 0) ++n;
  for (int k = 0; k < n; ++k) {
    const size_t len = s.size();
    const int what = *rc::gen::inRange(0, 13) % 10 == 4 ? 4 : *rc::gen::inRange(0, 10);
    const size_t at = len ? size_t(*rc::gen::inRange<size_t>(0, len)) : 0;
    switch (what) {
      case 0:  // flip a byte
        if (len) s[at] = char(s[at] ^ char(1 << *rc::gen::inRange(0, 8)));
        break;
      case 1:  // insert a random byte
        s.insert(s.begin() + long(at), char(*rc::gen::arbitrary<unsigned char>()));
        break;
      case 2: {  // delete a range
        const size_t l = std::min(len - std::min(at, len), size_t(*rc::gen::inRange(1, 64)));
        s.erase(at, l);
        break;
      }
      case 3: {  // duplicate a range
        const size_t l = std::min(len - std::min(at, len), size_t(*rc::gen::inRange(1, 200)));
        s.insert(at, s.substr(at, l));
        break;
      }
      case 4: {  // replace the number (or word) at `at` with a plausible or a hostile one
        size_t b = at, e = at;
        while (b > 0 && !std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
        while (e < len && !std::isspace(static_cast<unsigned char>(s[e]))) ++e;
        s.replace(b, e - b, *rc::gen::arbitrary<bool>() ? *rc::gen::elementOf(kPlausible) : *rc::gen::elementOf(kNumbers));
        break;
      }
      case 5: {  // insert a line
        std::string line;
        const int words = *rc::gen::inRange(1, 8);
        for (int w = 0; w < words; ++w) line += (w ? " " : "") + *token();
        const size_t nl = s.find('\n', at);
        s.insert(nl == std::string::npos ? len : nl + 1, line + "\n");
        break;
      }
      case 6:  // truncate
        s.resize(at);
        break;
      case 7: {  // change a polygon's vertex count
        const size_t p = s.find("\np ", at);
        if (p != std::string::npos) {
          const size_t e = s.find('\n', p + 1);
          s.replace(p + 1, (e == std::string::npos ? s.size() : e) - p - 1, "p " + *rc::gen::elementOf(kNumbers));
        }
        break;
      }
      case 8:  // a NUL byte
        s.insert(s.begin() + long(at), '\0');
        break;
      default: {  // swap two lines' order by moving a chunk to the end
        const size_t l = std::min(len - std::min(at, len), size_t(*rc::gen::inRange(1, 80)));
        const std::string chunk = s.substr(at, l);
        s.erase(at, l);
        s += chunk;
        break;
      }
    }
  }
  return s;
}

using lockstep::props::rc_run::fuzz;  // 50 times the usual case count (props/driver/rc_run.h)

TEST(FuzzNff, RandomBytes) {
  fuzz("fuzz_nff.random_bytes", [] {
    // Any bytes, or RapidCheck's characters (mostly printable).
    const std::string text =
        *rc::gen::arbitrary<bool>()
            ? *rc::gen::resize(400, rc::gen::container<std::string>(rc::gen::map(
                                        rc::gen::arbitrary<unsigned char>(), [](unsigned char c) { return char(c); })))
            : *rc::gen::resize(400, rc::gen::string<std::string>());
    parse_ok(text);
  });
}

TEST(FuzzNff, TokenSoup) {
  fuzz("fuzz_nff.token_soup", [] {
    const std::string text = *rc::gen::resize(rc::kNominalSize, rc::gen::exec([] {
      const int n = *rc::gen::inRange(0, 120);
      std::string t;
      if (*rc::gen::arbitrary<bool>()) t = "v\nfrom 0 0 1\nat 0 0 0\nup 0 1 0\nangle 45\nhither 0\nresolution 8 8\n";
      for (int i = 0; i < n; ++i) t += *token() + *separator();
      return t;
    }));
    parse_ok(text);
  });
}

TEST(FuzzNff, MutatedSpdFiles) {
  static const std::vector<std::string> files = seeds();
  ASSERT_FALSE(files.empty()) << "no seed files in " << LOCKSTEP_FUZZ_DATA_DIR;
  for (const std::string& f : files) {  // the seeds themselves parse
    EXPECT_NO_THROW(lockstep::parse_nff(f, "seed.nff"));
  }
  fuzz("fuzz_nff.mutated_spd", [] {
    const std::string& base = *rc::gen::elementOf(files);
    parse_ok(*rc::gen::resize(rc::kNominalSize, rc::gen::exec([&] { return mutate(base); })));
  });
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}

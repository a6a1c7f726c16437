// lockstep props/raster: the painter family's properties (painter_part).
//
//   PainterEqualsZbuffer.painter__<impl>   layered scenes (generator "layered":
//       2..7 triangles, each inside its own slab between parallel tilted planes,
//       in shuffled scene order, so that their depth ranges overlap but no
//       cycle or interpenetration exists): the painter's frame equals the
//       z-buffer's (ref::zbuffer): the same coverage (depth plane finite at the
//       same pixels), the same colour bit for bit (the painter draws the
//       z-buffer's fragments with its arithmetic; measured: 0 differences), and
//       no finding reported.
//   PainterReports.painter__<impl>__<gen>   cyclic triples (three long sticks,
//       each over the next at one crossing: "cyclic_triple") and
//       interpenetrating pairs ("interpenetrating_pair"), without split: every
//       pixel that differs from the z-buffer (in any bit of colour, or coverage)
//       has a sample covered by two triangles that the notes name ("tri N"):
//       the painter never draws a wrong image without reporting why.
//   PainterSplit.painter__<impl>__<gen>   the same scenes with split=1: no pixel
//       differs from the z-buffer (depth=double there, so that the z-buffer's
//       own depth rounding does not decide samples on an intersection line).
//   PainterExact.tri_tri__reference   exact::triangles_intersect and
//       exact::orient3d against CGAL's exact predicates (painter_oracle.h) on
//       random pairs, pairs on a small integer grid (shared vertices and edges,
//       coplanar, touching) and grid pairs nudged by a few ulps.
//   PainterFailureMap.painter   (fixed) the wrong-pixel fraction of the
//       reference painter without split on 100 cyclic triples and 100
//       interpenetrating pairs, printed; every cyclic triple must draw some
//       pixel wrong, and none may with split.
#include "reference/painter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <numeric>
#include <random>
#include <regex>
#include <set>
#include <sstream>

#include "core/error.h"
#include "io/nff.h"
#include "registry/registry.h"
#include "props/gen/numbers.h"
#include "props/property.h"
#include "props/raster/painter_oracle.h"
#include "props/raster/parts.h"
#include "props/raster/raster_case.h"

namespace lockstep::props::raster {

namespace {

using Uniform = std::function<double()>;  // uniform in [0, 1)

std::string vec(double x, double y, double z) {
  return num(x) + " " + num(y) + " " + num(z) + "\n";
}

std::string view_block(int w, int h) {
  return "v\nfrom 0 0 0\nat 0 0 -1\nup 0 1 0\nangle 40\nhither 1\nresolution " + std::to_string(w) +
         " " + std::to_string(h) + "\nb 0.1 0.1 0.2\nl 4 5 10\nl -6 2 8 0.6 0.6 0.6\n";
}

std::string material(const Uniform& u, bool two_sided) {
  return "f " + num(0.2 + 0.8 * u()) + " " + num(0.2 + 0.8 * u()) + " " + num(0.2 + 0.8 * u()) +
         " 0.8 " + num(0.4 * u()) + " 12 " + (two_sided ? "0.5" : "0") + " 1\n";
}

// Layered: triangle k lies in slab s_k = {d0 + s gap + m <= n.p <= d0 + (s+1) gap - m}
// of parallel planes with unit normal n facing away from the eye (at the origin).
// Whatever the tilt, the slabs nearer the eye hide the farther ones: an order exists.
std::string layered_nff(const Uniform& u, int w, int h) {
  std::string s = view_block(w, h);
  const double half = std::tan(20.0 * M_PI / 180.0);
  const double a = 1.6 * u() - 0.8, b = 1.6 * u() - 0.8;
  const Vec3 n = normalize(Vec3(a, b, -1));
  const int count = 2 + int(6 * u());
  const double d0 = 3, gap = 1.5, margin = 0.2;
  std::vector<int> slab(count);
  std::iota(slab.begin(), slab.end(), 0);
  for (int i = count - 1; i > 0; --i) std::swap(slab[i], slab[int(u() * (i + 1)) % (i + 1)]);
  for (int k = 0; k < count; ++k) {
    s += material(u, u() < 0.75) + "p 3\n";
    for (int v = 0; v < 3; ++v) {
      const Vec3 dir((2.4 * u() - 1.2) * half, (2.4 * u() - 1.2) * half, -1);
      const double target = d0 + slab[k] * gap + margin + (gap - 2 * margin) * u();
      const Vec3 p = dir * (target / dot(n, dir));  // on the ray, at n.p = target
      s += vec(p.x, p.y, p.z);
    }
  }
  return s;
}

// Three sticks (thin quads) rotated 120 degrees apart around the view axis,
// each tilted in depth: each lies over the next at one crossing and under the
// previous at the other (the classic cycle).
std::string cyclic_triple_nff(const Uniform& u, int w, int h) {
  std::string s = view_block(w, h);
  const double th0 = 2 * M_PI * u(), cx = 0.6 * u() - 0.3, cy = 0.6 * u() - 0.3;
  const double len = 2.6 + 0.8 * u(), width = 0.2 + 0.2 * u(), off = 0.7 + 0.4 * u();
  const double slope = (u() < 0.5 ? -1 : 1) * (0.15 + 0.2 * u());
  for (int i = 0; i < 3; ++i) {
    const double th = th0 + 2 * M_PI * i / 3;
    const double ux = std::cos(th), uy = std::sin(th), nx = -uy, ny = ux;
    s += material(u, true) + "p 4\n";
    const double corners[4][2] = {{-len, -width}, {len, -width}, {len, width}, {-len, width}};
    for (const auto& [t, q] : corners) {
      const double x = cx + off * nx + t * ux + q * nx + 0.05 * (u() - 0.5);
      const double y = cy + off * ny + t * uy + q * ny + 0.05 * (u() - 0.5);
      const double z = -10 + slope * t + 0.05 * (u() - 0.5);
      s += vec(x, y, z);
    }
  }
  return s;
}

// Two triangles that pass through each other (an X seen from the side), turned
// about the view axis, every coordinate jittered.
std::string interpenetrating_pair_nff(const Uniform& u, int w, int h) {
  std::string s = view_block(w, h);
  const double th = 2 * M_PI * u(), c = std::cos(th), sn = std::sin(th);
  const double tri[2][3][3] = {{{-2.5, -2, -1.2}, {2.5, -2, 1.2}, {0, 2.5, 0}},
                               {{-2.5, -1.5, 1.0}, {2.5, -1.5, -1.0}, {0.3, 2.2, 0.1}}};
  for (const auto& t : tri) {
    s += material(u, true) + "p 3\n";
    for (const auto& p : t) {
      const double x = p[0] + 0.6 * (u() - 0.5), y = p[1] + 0.6 * (u() - 0.5),
                   z = p[2] + 0.6 * (u() - 0.5);
      s += vec(c * x - sn * y, sn * x + c * y, z - 10);
    }
  }
  return s;
}

using SceneMaker = std::string (*)(const Uniform&, int, int);

// A RasterCase from a scene maker, its numbers drawn by RapidCheck.
rc::Gen<RasterCase> case_gen(SceneMaker make, bool split) {
  return rc::gen::exec([make, split] {
    RasterCase c;
    c.width = int(*gen::int_in(16, 64));
    c.height = int(*gen::int_in(16, 64));
    const Uniform u = [] { return *gen::uniform(0, 1); };
    c.nff = make(u, c.width, c.height);
    c.params.set("shading", *gen::chance(1, 2) ? "phong" : "flat");
    if (*gen::chance(1, 4)) c.params.set("spp", "4");
    if (split) {
      c.params.set("split", "1");
      c.params.set("depth", "double");
    }
    return c;
  });
}

// The triangles a run's notes name ("tri N (prim P)").
std::set<uint32_t> reported_tris(const std::vector<std::string>& notes) {
  std::set<uint32_t> out;
  static const std::regex re("tri ([0-9]+) \\(prim");
  for (const std::string& n : notes)
    for (auto it = std::sregex_iterator(n.begin(), n.end(), re); it != std::sregex_iterator(); ++it)
      out.insert(uint32_t(std::stoul((*it)[1].str())));
  return out;
}

// Per pixel: the largest number of the given triangles covering one of its samples.
std::vector<int> cover_count(const Scene& scene, const RasterCase& c,
                             const std::set<uint32_t>& which) {
  const RasterSettings s = raster_settings(c.params, "<case>");
  const ScreenMesh mesh = view_scene(scene, c.width, c.height, s);
  const auto offsets = sample_offsets(s);
  std::vector<int> most(size_t(c.width) * c.height, 0);
  for (int j = 0; j < c.height; ++j)
    for (int i = 0; i < c.width; ++i)
      for (const auto& o : offsets) {
        const int64_t sx = int64_t(i) * kSubpixel + o[0], sy = int64_t(j) * kSubpixel + o[1];
        int n = 0;
        for (uint32_t t : which) {
          if (t >= mesh.tris.size()) continue;
          const PainterTri pt = painter_tri(mesh.tris[t]);
          std::array<int64_t, 3> e;
          for (int v = 0; v < 3; ++v) {
            const int a = (v + 1) % 3, b = (v + 2) % 3;
            e[v] = (pt.x[b] - pt.x[a]) * (sy - pt.y[a]) - (pt.y[b] - pt.y[a]) * (sx - pt.x[a]);
          }
          n += painter_covers(mesh.tris[t], e);
        }
        int& m = most[size_t(j) * c.width + i];
        m = std::max(m, n);
      }
  return most;
}

struct Frames {
  Image painter, zbuffer;
  std::vector<std::string> notes;
};

Frames render_both(const FamilyImpl& impl, const RasterCase& c) {
  const auto scene = c.scene();
  const Input in = make_input<Scene>(*scene, "<case>", c.width, c.height, scene->background);
  Frames f;
  FrameStats st;
  f.painter = impl.run_as<Image>(in, c.options(), &st);
  f.notes = st.notes;
  FrameStats zs;
  f.zbuffer = registry().find("zbuffer")->reference().run_as<Image>(in, c.options(), &zs);
  return f;
}

// Pixel (i, j) of the two frames: colour error, and whether coverage differs.
double pixel_error(const Frames& f, int i, int j, bool& coverage_differs) {
  const float* a = f.painter.pixel(i, j);
  const float* b = f.zbuffer.pixel(i, j);
  double err = 0;
  for (int k = 0; k < 3; ++k) err = std::max(err, double(std::abs(a[k] - b[k])));
  const size_t idx = size_t(j) * f.painter.width + i;
  coverage_differs = std::isinf(f.painter.depth[idx]) != std::isinf(f.zbuffer.depth[idx]);
  return coverage_differs ? kInfinity : err;
}

std::string pixel_detail(const FamilyImpl& impl, const Frames& f, int i, int j, double err) {
  const float* a = f.painter.pixel(i, j);
  const float* b = f.zbuffer.pixel(i, j);
  std::ostringstream d;
  d << "pixel (" << i << ", " << j << "): painter " << impl.name << " (" << a[0] << ", " << a[1]
    << ", " << a[2] << ") depth " << f.painter.depth[size_t(j) * f.painter.width + i]
    << " vs z-buffer (" << b[0] << ", " << b[1] << ", " << b[2] << ") depth "
    << f.zbuffer.depth[size_t(j) * f.zbuffer.width + i] << ", error " << err << "; notes:";
  for (const auto& n : f.notes) d << " [" << n << "]";
  return d.str();
}

// Layered scenes: equal to the z-buffer, nothing reported.
Verdict equals_zbuffer(const FamilyImpl& impl, const RasterCase& c) {
  const Frames f = render_both(impl, c);
  Verdict v;
  if (!f.notes.empty()) {
    Outcome o;
    o.kind = Outcome::unexplained;
    o.label = "false_report";
    o.detail = "a scene with an order reported findings:";
    for (const auto& n : f.notes) o.detail += " [" + n + "]";
    v.rays.push_back(o);
  }
  for (int j = 0; j < c.height; ++j)
    for (int i = 0; i < c.width; ++i) {
      bool cov = false;
      Outcome o;
      o.err = pixel_error(f, i, j, cov);
      o.measured = !cov;
      o.unit = "colour";
      if (cov || o.err > 0) {
        o.kind = Outcome::unexplained;
        o.label = cov ? "coverage" : "colour";
        o.detail = pixel_detail(impl, f, i, j, o.err);
      }
      v.rays.push_back(o);
    }
  return v;
}

// Cyclic and interpenetrating scenes: every differing pixel reported (no
// split), or none differing (split).
Verdict reports_or_splits(const FamilyImpl& impl, const RasterCase& c, bool split) {
  const Frames f = render_both(impl, c);
  const auto scene = c.scene();
  const std::vector<int> covered = cover_count(*scene, c, reported_tris(f.notes));
  Verdict v;
  for (int j = 0; j < c.height; ++j)
    for (int i = 0; i < c.width; ++i) {
      bool cov = false;
      Outcome o;
      o.err = pixel_error(f, i, j, cov);
      o.measured = !cov;
      o.unit = "colour";
      if (cov || o.err > 0) {
        const bool reported = covered[size_t(j) * c.width + i] >= 2;
        o.kind = !split && reported ? Outcome::explained : Outcome::unexplained;
        o.label = split ? "split_differs" : (reported ? "reported" : "unreported");
        o.detail = pixel_detail(impl, f, i, j, o.err);
      }
      v.rays.push_back(o);
    }
  return v;
}

Property frame_property(const Family& family, const FamilyImpl& impl, const std::string& suite,
                        const std::string& check, const std::string& gen_name, SceneMaker make,
                        bool split,
                        std::function<Verdict(const FamilyImpl&, const RasterCase&)> judge) {
  Property p;
  p.family = std::string(family.name);
  p.check = check;
  p.suite = suite;
  p.name = std::string(family.name) + "__" + std::string(impl.name) +
           (gen_name == "layered" ? "" : "__" + gen_name);
  p.generator = gen_name;
  p.pair = std::string(family.name);
  p.impl = std::string(impl.name);
  p.bound = 0;
  p.unit = "colour";
  p.units = "pixels";
  const auto g = std::make_shared<const rc::Gen<RasterCase>>(case_gen(make, split));
  p.run = [g, &impl, judge] {
    auto c = std::make_shared<const RasterCase>(**g);
    Ran r;
    r.verdict = judge(impl, *c);
    r.text = [c](long) { return write_case(*c); };
    return r;
  };
  p.replay = [&impl, judge](const std::string& text, const std::string& file) {
    return judge(impl, read_case(text, file));
  };
  return p;
}

// ---------------------------------------------------------------- the exact predicates

// A case of the tri-tri check: triangle pairs, 18 numbers a line (hexfloats).
struct PairsCase {
  std::vector<std::array<std::array<Vec3, 3>, 2>> pairs;
};

std::string write_pairs(const PairsCase& c) {
  std::string s = "tri_tri_pairs " + std::to_string(c.pairs.size()) + "\n";
  char buf[40];
  for (const auto& pr : c.pairs) {
    for (const auto& t : pr)
      for (const Vec3& v : t)
        for (int k = 0; k < 3; ++k) {
          std::snprintf(buf, sizeof buf, "%a ", v[k]);
          s += buf;
        }
    s += "\n";
  }
  return s;
}

PairsCase read_pairs(const std::string& text, const std::string& file) {
  std::istringstream in(text.substr(std::min(text.size(), text.find("tri_tri_pairs"))));
  std::string head;
  size_t n = 0;
  if (!(in >> head >> n) || head != "tri_tri_pairs")
    throw InputError(file, 0, "expected 'tri_tri_pairs N'");
  PairsCase c;
  c.pairs.resize(n);
  for (auto& pr : c.pairs)
    for (auto& t : pr)
      for (Vec3& v : t)
        for (int k = 0; k < 3; ++k) {
          std::string w;
          if (!(in >> w)) throw InputError(file, 0, "short pair list");
          v[k] = std::strtod(w.c_str(), nullptr);
        }
  return c;
}

rc::Gen<PairsCase> pairs_gen() {
  return rc::gen::exec([] {
    PairsCase c;
    for (int n = 0; n < 32; ++n) {
      std::array<std::array<Vec3, 3>, 2> pr;
      const int kind = int(*gen::int_in(0, 3));
      auto grid = [] { return double(*gen::int_in(-3, 3)) * 0.5; };
      for (auto& t : pr)
        for (Vec3& v : t)
          v = kind == 0 ? Vec3(*gen::uniform(-1, 1), *gen::uniform(-1, 1), *gen::uniform(-1, 1))
                        : Vec3(grid(), grid(), grid());
      if (kind == 2) {  // share a vertex or an edge
        pr[1][0] = pr[0][int(*gen::int_in(0, 2))];
        if (*gen::chance(1, 2)) pr[1][1] = pr[0][int(*gen::int_in(0, 2))];
      }
      if (kind == 3) {  // nudge one coordinate of a grid pair by a few ulps
        Vec3& v = pr[*gen::int_in(0, 1)][*gen::int_in(0, 2)];
        const int axis = int(*gen::int_in(0, 2));
        v[axis] = gen::nudge(v[axis], *gen::int_in(-3, 3));
      }
      // Non-degenerate triangles only (the predicate's precondition).
      if (oracle_collinear(pr[0][0], pr[0][1], pr[0][2]) ||
          oracle_collinear(pr[1][0], pr[1][1], pr[1][2]))
        continue;
      c.pairs.push_back(pr);
    }
    return c;
  });
}

// Whether the expansions of Shewchuk's predicates may underflow on the pair
// (their one precondition: no product's rounding error below the smallest
// subnormal): a nonzero coordinate, or difference of two coordinates on an
// axis, below 2^-300 (triple products of such numbers reach 2^-900, their
// error terms 2^-1060 and less). The generator's ulp nudges of 0 make
// subnormal coordinates; scenes' eye coordinates are nowhere near.
bool may_underflow(const std::array<Vec3, 3>& t, const std::array<Vec3, 3>& u) {
  std::array<Vec3, 6> p = {t[0], t[1], t[2], u[0], u[1], u[2]};
  for (int k = 0; k < 3; ++k)
    for (size_t i = 0; i < p.size(); ++i) {
      const double a = std::abs(p[i][k]);
      if (a != 0 && a < 0x1p-300) return true;
      for (size_t j = i + 1; j < p.size(); ++j) {
        const double d = std::abs(p[i][k] - p[j][k]);
        if (d != 0 && d < 0x1p-300) return true;
      }
    }
  return false;
}

Verdict check_pairs(const PairsCase& c) {
  Verdict v;
  for (const auto& [t, u] : c.pairs) {
    Outcome o;
    o.unit = "decision";
    const bool got = exact::triangles_intersect(t, u), want = oracle_triangles_intersect(t, u);
    std::string why;
    if (got != want)
      why = std::string("triangles_intersect ") + (got ? "true" : "false") + ", CGAL " +
            (want ? "true" : "false");
    // orient3d of every vertex of u against t's plane (ours is -CGAL's orientation).
    for (int k = 0; k < 3 && why.empty(); ++k) {
      const int a = exact::orient3d(t[0], t[1], t[2], u[k]),
                b = -oracle_orientation(t[0], t[1], t[2], u[k]);
      if (a != b)
        why = "orient3d of u[" + std::to_string(k) + "]: " + std::to_string(a) + ", CGAL " +
              std::to_string(b);
    }
    if (!why.empty()) {
      // Outside the predicates' domain (underflow) the disagreement is the
      // method's known limit, labelled; inside it, a bug.
      const bool underflow = may_underflow(t, u);
      o.kind = underflow ? Outcome::explained : Outcome::unexplained;
      o.label = underflow ? "underflow" : "differs";
      o.err = 1;
      o.detail = why + "; pair: " + write_pairs(PairsCase{{{t, u}}});
    }
    v.rays.push_back(o);
  }
  return v;
}

Property exact_property(const Family& family) {
  Property p;
  p.family = std::string(family.name);
  p.check = "exact";
  p.suite = "PainterExact";
  p.name = "tri_tri__reference";
  p.generator = "triangle_pairs";
  p.pair = "tri_tri";
  p.impl = "reference";
  p.bound = 0;
  p.unit = "decision";
  p.units = "pairs";
  const auto g = std::make_shared<const rc::Gen<PairsCase>>(pairs_gen());
  p.run = [g] {
    auto c = std::make_shared<const PairsCase>(**g);
    Ran r;
    r.verdict = check_pairs(*c);
    r.text = [c](long) { return write_pairs(*c); };
    return r;
  };
  p.replay = [](const std::string& text, const std::string& file) {
    return check_pairs(read_pairs(text, file));
  };
  return p;
}

// ---------------------------------------------------------------- the failure map

void failure_map(const Family& family) {
  for (const char* kind : {"cyclic_triple", "interpenetrating_pair"}) {
    const std::vector<PainterMapCase> cases =
        painter_failure_map(family.reference(), kind, 100, 20261125);
    double sum = 0, lo = 1, hi = 0, wrong_split = 0;
    int reported = 0, with_wrong = 0;
    for (const PainterMapCase& c : cases) {
      sum += c.wrong_fraction;
      lo = std::min(lo, c.wrong_fraction);
      hi = std::max(hi, c.wrong_fraction);
      with_wrong += c.wrong > 0;
      reported += c.reported;
      wrong_split += c.wrong_split;
      if (kind == std::string("cyclic_triple")) {
        EXPECT_GT(c.wrong, 0) << "a cyclic triple drawn right in depth order:\n" << c.nff;
      }
      EXPECT_TRUE(c.wrong == 0 || c.reported) << "wrong pixels, nothing reported:\n" << c.nff;
      EXPECT_EQ(c.wrong_split, 0) << "split differs from the z-buffer:\n" << c.nff;
    }
    std::printf(
        "painter failure map, %s (64x64, flat, %zu cases): wrong pixels / covered pixels mean "
        "%.4f, "
        "min %.4f, max %.4f; %d cases with wrong pixels, %d reported; with split: %.0f wrong "
        "pixels in all\n",
        kind, cases.size(), sum / double(cases.size()), lo, hi, with_wrong, reported, wrong_split);
  }
}

}  // namespace

std::vector<PainterMapCase> painter_failure_map(const FamilyImpl& impl, const std::string& kind,
                                                int cases, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> dist(0, 1);
  const Uniform u = [&] { return dist(rng); };
  const SceneMaker make = kind == "cyclic_triple" ? cyclic_triple_nff : interpenetrating_pair_nff;
  std::vector<PainterMapCase> out;
  for (int n = 0; n < cases; ++n) {
    RasterCase c;
    c.width = c.height = 64;
    c.nff = make(u, c.width, c.height);
    c.params.set("shading", "flat");
    PainterMapCase m;
    m.nff = c.nff;
    const Frames f = render_both(impl, c);
    // Wrong pixels (coverage or colour differs from the z-buffer's), over the
    // pixels the scene covers.
    int covered = 0;
    for (int j = 0; j < c.height; ++j)
      for (int i = 0; i < c.width; ++i) {
        bool cov = false;
        const double err = pixel_error(f, i, j, cov);
        covered += !std::isinf(f.zbuffer.depth[size_t(j) * c.width + i]);
        m.wrong += cov || err > 0;
      }
    m.wrong_fraction = covered ? double(m.wrong) / covered : 0;
    m.reported = !f.notes.empty();
    // With split (and the z-buffer in double depth, as exact as the splits): nothing wrong.
    c.params.set("split", "1");
    c.params.set("depth", "double");
    const Frames fs = render_both(impl, c);
    for (int j = 0; j < c.height; ++j)
      for (int i = 0; i < c.width; ++i) {
        bool cov = false;
        const double err = pixel_error(fs, i, j, cov);
        m.wrong_split += cov || err > 0;
      }
    out.push_back(std::move(m));
  }
  return out;
}

void painter_part(const Family& family, FamilyProperties& out) {
  for (const FamilyImpl& impl : family.impls) {
    out.properties.push_back(frame_property(family, impl, "PainterEqualsZbuffer", "equals_zbuffer",
                                            "layered", layered_nff, false, equals_zbuffer));
    for (const auto& [name, make] :
         {std::pair<std::string, SceneMaker>{"cyclic_triple", cyclic_triple_nff},
          std::pair<std::string, SceneMaker>{"interpenetrating_pair", interpenetrating_pair_nff}}) {
      out.properties.push_back(frame_property(
          family, impl, "PainterReports", "reports", name, make, false,
          [](const FamilyImpl& i, const RasterCase& c) { return reports_or_splits(i, c, false); }));
      out.properties.push_back(frame_property(
          family, impl, "PainterSplit", "split", name, make, true,
          [](const FamilyImpl& i, const RasterCase& c) { return reports_or_splits(i, c, true); }));
    }
  }
  out.properties.push_back(exact_property(family));
  out.fixed.push_back({"PainterFailureMap", "painter", [&family] { failure_map(family); }});
}

}  // namespace lockstep::props::raster

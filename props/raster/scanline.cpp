// lockstep props/raster: the scanline family's properties (part "scanline").
//
//   ScanlineCoverage.scanline__<impl>   on random snapped screen meshes
//       (triangle soups and closed fans, vertices often exactly on sample rows
//       and columns, every depth format, 1/4/9 samples per pixel on regular and
//       rotated grids) the scanline's coverage count equals
//       ref::zbuffer_visibility's sample for sample (unit: a sample; any
//       difference is unexplained), the visible triangle is the same unless the
//       two candidates' exact stored depths at the sample are within the depth
//       format's tie band ("depth_tie"), and where the triangle is the same the
//       stored depths agree within the implementation's drift bound (in units of
//       the format's resolution: float ulps, 24-bit steps, double ulps).
//   ScanlineEqualsZbuffer.scanline__<impl>   on the NFF triangle soups of
//       raster_case.h (Phong, culling), the frame equals ref::zbuffer's within
//       1/255 per pixel; a pixel over it is explained only when its centre's
//       visible triangle differs at a depth tie.
#include "optimized/scanline_simd.h"

#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "core/error.h"
#include "registry/registry.h"
#include "props/gen/numbers.h"
#include "props/property.h"
#include "props/raster/parts.h"
#include "props/raster/raster_case.h"
#include "reference/scanline.h"

namespace lockstep::props::raster {

namespace {

// ---------------------------------------------------------------- the case: a snapped screen mesh

struct MeshCase {
  int width = 8, height = 8, spp = 1;
  bool rotated = false;
  DepthFormat depth = DepthFormat::kFloat;
  std::vector<std::array<ScreenVertex, 3>> tris;  // positive area, x and y in 1/256 pixel

  RasterSettings settings() const {
    RasterSettings s;
    s.spp = spp;
    s.grid = rotated ? SampleGrid::kRotated : SampleGrid::kRegular;
    s.depth = depth;
    return s;
  }
  ScreenMesh mesh() const {
    ScreenMesh m;
    m.width = width;
    m.height = height;
    m.near_z = 0.5;
    m.far_z = 64;
    for (const auto& t : tris) {
      ScreenTri st;
      st.v = t;
      m.tris.push_back(st);
    }
    return m;
  }
};

constexpr const char* kMeshHeader = "scanline_mesh";
const char* kFormats[] = {"float", "reversed", "fixed24", "double"};

std::string write_mesh(const MeshCase& c) {
  std::ostringstream o;
  o << kMeshHeader << " " << c.width << " " << c.height << " " << c.spp << " "
    << (c.rotated ? "rotated" : "regular") << " " << kFormats[int(c.depth)] << "\n";
  char buf[64];
  for (const auto& t : c.tris) {
    for (const ScreenVertex& v : t) {
      std::snprintf(buf, sizeof buf, "%a", v.z);
      o << v.x << " " << v.y << " " << buf << "  ";
    }
    o << "\n";
  }
  return o.str();
}

MeshCase read_mesh(const std::string& text, const std::string& file) {
  const size_t at = text.starts_with(kMeshHeader) ? 0 : text.find(std::string("\n") + kMeshHeader);
  if (at == std::string::npos)
    throw InputError(file, 0, "no 'scanline_mesh W H SPP GRID DEPTH' line");
  std::istringstream in(text.substr(at == 0 ? 0 : at + 1));
  MeshCase c;
  std::string head, grid, depth;
  if (!(in >> head >> c.width >> c.height >> c.spp >> grid >> depth) || c.width < 1 || c.height < 1)
    throw InputError(file, 0, "bad 'scanline_mesh W H SPP GRID DEPTH' line");
  c.rotated = grid == "rotated";
  for (int f = 0; f < 4; ++f)
    if (depth == kFormats[f]) c.depth = DepthFormat(f);
  std::string z[3];
  std::array<ScreenVertex, 3> t;
  while (in >> t[0].x >> t[0].y >> z[0] >> t[1].x >> t[1].y >> z[1] >> t[2].x >> t[2].y >> z[2]) {
    for (int k = 0; k < 3; ++k) t[k].z = std::strtod(z[k].c_str(), nullptr);
    c.tris.push_back(t);
  }
  return c;
}

int64_t area2(const std::array<ScreenVertex, 3>& t) {
  return int64_t(t[1].x - t[0].x) * (t[2].y - t[0].y) -
         int64_t(t[1].y - t[0].y) * (t[2].x - t[0].x);
}

// Keeps a triangle with positive area (swapping two vertices of a negative one).
void add_tri(MeshCase& c, std::array<ScreenVertex, 3> t) {
  const int64_t a = area2(t);
  if (a == 0) return;
  if (a < 0) std::swap(t[1], t[2]);
  c.tris.push_back(t);
}

// Random snapped meshes: coordinates on a lattice of 1, 32, 64 or 128 units
// (128: every other lattice point is a pixel centre, so vertices and edges pass
// exactly through samples), a margin of two pixels off screen; a soup of up to
// 10 triangles, or a closed fan of 3..12 triangles around a centre (shared edges,
// each interior sample owned once).
rc::Gen<MeshCase> snapped_mesh() {
  return rc::gen::exec([] {
    MeshCase c;
    c.width = int(*gen::int_in(4, 24));
    c.height = int(*gen::int_in(4, 24));
    const int n = int(*gen::int_in(1, 3));
    c.spp = n * n;
    c.rotated = *gen::chance(1, 2);
    c.depth = DepthFormat(*gen::int_in(0, 3));
    const int lattice = *rc::gen::element(128, 64, 32, 1);
    auto coord = [&](int pixels) {
      const int64_t lo = -2 * kSubpixel / lattice, hi = (pixels + 2) * kSubpixel / lattice;
      return int32_t(*gen::int_in(lo, hi) * lattice);
    };
    auto depth = [] { return *gen::uniform(1, 32); };
    if (*gen::chance(1, 2)) {
      const int tris = int(*gen::int_in(1, 10));
      for (int i = 0; i < tris; ++i) {
        std::array<ScreenVertex, 3> t;
        for (auto& v : t) {
          v.x = coord(c.width);
          v.y = coord(c.height);
          v.z = depth();
        }
        add_tri(c, t);
      }
    } else {
      ScreenVertex centre;
      centre.x = coord(c.width);
      centre.y = coord(c.height);
      centre.z = depth();
      const int k = int(*gen::int_in(3, 12));
      const double radius = *gen::uniform(1, 12) * kSubpixel;
      const double phase = *gen::uniform(0, 6.283185307179586);
      std::vector<ScreenVertex> ring(static_cast<size_t>(k));
      for (int i = 0; i < k; ++i) {
        const double angle = phase + 6.283185307179586 * i / k;
        ring[size_t(i)].x =
            int32_t(std::lround((centre.x + radius * std::cos(angle)) / lattice) * lattice);
        ring[size_t(i)].y =
            int32_t(std::lround((centre.y + radius * std::sin(angle)) / lattice) * lattice);
        ring[size_t(i)].z = depth();
      }
      for (int i = 0; i < k; ++i) add_tri(c, {centre, ring[size_t(i)], ring[size_t((i + 1) % k)]});
    }
    return c;
  });
}

// ---------------------------------------------------------------- the coverage check

// The exact stored depth of triangle t at sample (px, py) (1/256 pixel): the
// screen barycentrics from the integer edge functions, 1/z in long double.
double exact_depth(const ScreenMesh& m, const RasterSettings& s, uint32_t ti, int64_t px,
                   int64_t py) {
  const ScreenTri& t = m.tris[ti];
  auto e = [&](const ScreenVertex& a, const ScreenVertex& b) {
    return (long double)(int64_t(b.x - a.x) * (py - a.y) - int64_t(b.y - a.y) * (px - a.x));
  };
  const long double A = (long double)(int64_t(t.v[1].x - t.v[0].x) * (t.v[2].y - t.v[0].y) -
                                      int64_t(t.v[1].y - t.v[0].y) * (t.v[2].x - t.v[0].x));
  const long double w = e(t.v[1], t.v[2]) / A / t.v[0].z + e(t.v[2], t.v[0]) / A / t.v[1].z +
                        e(t.v[0], t.v[1]) / A / t.v[2].z;
  return stored_depth(s.depth, double(1 / w), m.near_z, m.far_z);
}

// The resolution of a stored depth value (what one unit of error is).
double resolution(DepthFormat f, double d) {
  switch (f) {
    case DepthFormat::kFloat:
    case DepthFormat::kReversed:
      return std::max(double(std::nextafter(float(std::abs(d)), FLT_MAX)) - std::abs(d),
                      double(FLT_MIN));
    case DepthFormat::kFixed24:
      return 1;
    case DepthFormat::kDouble:
      break;
  }
  return std::max(std::nextafter(std::abs(d), DBL_MAX) - std::abs(d), DBL_MIN);
}

// How many units of resolution (at the triangle's largest stored depth) two
// depths of the same triangle at the same sample may differ by. Reference:
// 1/z drifts by ulps of a double along a span (measured at most 15 units on
// 2000 snapped meshes of spans <= 28 px), which a float or a 24-bit rounding
// hides but for one unit at a rounding boundary. Simd: the depth from the plane
// in double, then float lanes: float rounding of the start, the step and each
// vector step (measured at most 2 units float, 1 reversed, 24 double).
double depth_bound(const std::string& impl, DepthFormat f) {
  if (impl == "reference") return f == DepthFormat::kDouble ? 32 : 1;
  switch (f) {
    case DepthFormat::kFloat:
      return 4;
    case DepthFormat::kReversed:
      return 2;
    case DepthFormat::kFixed24:
      return 1;
    case DepthFormat::kDouble:
      break;
  }
  return 48;
}

// Two triangles at a depth tie: their exact stored depths within the tie band.
bool depth_tie(DepthFormat f, double a, double b) {
  return std::abs(a - b) <= 4 * resolution(f, std::max(std::abs(a), std::abs(b)));
}

// A scanline visibility pass under test: the kernel-level entry point of a
// row of the family (the registry rows carry only frames).
using VisibilityFn = std::function<void(const ScreenMesh&, const RasterSettings&, Visibility&)>;

// The visibility pass of the family's implementation `impl`, or an empty
// function when it has none.
VisibilityFn visibility_of(std::string_view impl) {
  if (impl == "reference") return ref::scanline_visibility;
  if (impl == "simd")
    return [](const ScreenMesh& m, const RasterSettings& s, Visibility& v) {
      opt::simd::scanline_visibility(m, s, 1, v);
    };
  return {};
}

// Deliberately broken scanlines (Mutants.scanline__<name>): each must fail the
// coverage property.
struct CoverageMutant {
  const char* name;
  const char* what;
  VisibilityFn fn;
};
std::vector<CoverageMutant> coverage_mutants() {
  return {
      {"edge_walk_off_by_one",
       "the edge crossings one 1/256 pixel to the right (the reference on a moved mesh)",
       [](const ScreenMesh& m, const RasterSettings& s, Visibility& v) {
         ScreenMesh moved = m;
         for (ScreenTri& t : moved.tris)
           for (ScreenVertex& x : t.v) x.x += 1;
         ref::scanline_visibility(moved, s, v);
       }},
  };
}

Verdict check_coverage(const std::string& impl, const VisibilityFn& scan, const MeshCase& c) {
  const ScreenMesh m = c.mesh();
  const RasterSettings s = c.settings();
  Visibility zb, sl;
  ref::zbuffer_visibility(m, s, zb);
  scan(m, s, sl);
  const auto offsets = sample_offsets(s);
  const int spp = int(offsets.size());
  Verdict v;
  for (int j = 0; j < c.height; ++j)
    for (int i = 0; i < c.width; ++i)
      for (int k = 0; k < spp; ++k) {
        const size_t x = (size_t(j) * c.width + i) * spp + k;
        const int64_t px = int64_t(i) * kSubpixel + offsets[k][0],
                      py = int64_t(j) * kSubpixel + offsets[k][1];
        Outcome o;
        std::ostringstream d;
        d << "sample (" << px << ", " << py << ") of pixel (" << i << ", " << j << "), k " << k
          << ": zbuffer count " << zb.count[x] << " tri "
          << int64_t(zb.tri[x] == Visibility::kNone ? -1 : zb.tri[x]) << " depth " << zb.depth[x]
          << "; scanline " << impl << " count " << sl.count[x] << " tri "
          << int64_t(sl.tri[x] == Visibility::kNone ? -1 : sl.tri[x]) << " depth " << sl.depth[x];
        if (zb.count[x] != sl.count[x]) {
          o.kind = Outcome::unexplained;
          o.label = "coverage";
          o.detail = d.str();
        } else if (zb.tri[x] != sl.tri[x]) {
          const double a = exact_depth(m, s, zb.tri[x], px, py),
                       b = exact_depth(m, s, sl.tri[x], px, py);
          const bool tie = zb.tri[x] != Visibility::kNone && sl.tri[x] != Visibility::kNone &&
                           depth_tie(s.depth, a, b);
          o.kind = tie ? Outcome::explained : Outcome::unexplained;
          o.label = tie ? "depth_tie" : "visible_triangle";
          d << "; exact depths " << a << " and " << b;
          o.detail = d.str();
        } else if (zb.tri[x] != Visibility::kNone) {
          // In units of the format's resolution at the triangle's largest
          // stored depth (every value on the triangle lies between its
          // vertices'): what evaluating an affine function in the format costs.
          const ScreenTri& t = m.tris[zb.tri[x]];
          double scale = 0;
          for (const ScreenVertex& vx : t.v)
            scale = std::max(scale,
                             std::abs(stored_depth(DepthFormat::kDouble, vx.z, m.near_z, m.far_z)));
          if (s.depth == DepthFormat::kReversed)
            for (const ScreenVertex& vx : t.v) scale = std::max(scale, m.near_z / vx.z);
          o.err = std::abs(zb.depth[x] - sl.depth[x]) / resolution(s.depth, scale);
          o.measured = true;
          o.unit = std::string("depth units (") + kFormats[int(s.depth)] + ")";
          if (o.err > depth_bound(impl, s.depth)) {
            o.kind = Outcome::unexplained;
            o.label = "depth";
            d << "; depth error " << o.err << " units of resolution, bound "
              << depth_bound(impl, s.depth);
            o.detail = d.str();
          }
        }
        v.rays.push_back(o);
      }
  return v;
}

Property coverage_property(const Family& family, const std::string& impl, VisibilityFn scan) {
  Property p;
  p.family = std::string(family.name);
  p.check = "scanline_coverage";
  p.suite = "ScanlineCoverage";
  p.name = std::string(family.name) + "__" + impl;
  p.generator = "snapped_mesh";
  p.pair = std::string(family.name);
  p.impl = impl;
  p.bound = 1;
  p.unit = "depth resolution units";
  p.units = "samples";
  const auto gen = std::make_shared<const rc::Gen<MeshCase>>(snapped_mesh());
  p.run = [gen, impl, scan] {
    auto c = std::make_shared<const MeshCase>(**gen);
    Ran r;
    r.verdict = check_coverage(impl, scan, *c);
    r.text = [c](long) { return write_mesh(*c); };
    return r;
  };
  p.replay = [impl, scan](const std::string& text, const std::string& file) {
    return check_coverage(impl, scan, read_mesh(text, file));
  };
  return p;
}

// ---------------------------------------------------------------- the frame against the z-buffer

Verdict check_frame(const FamilyImpl& impl, const RasterCase& c) {
  const auto scene = c.scene();
  const Input in = make_input<Scene>(*scene, "<case>", c.width, c.height, scene->background);
  const FrameOptions o = c.options();
  FrameStats st;
  const Image a = impl.run_as<Image>(in, o, &st);
  const Image b = registry().find("zbuffer")->reference().run_as<Image>(in, o, &st);
  // The visible triangles, for explaining a difference.
  const RasterSettings s = raster_settings(c.params, "<case>");
  const ScreenMesh m = view_scene(*scene, c.width, c.height, s);
  Visibility zb, sl;
  ref::zbuffer_visibility(m, s, zb);
  ref::scanline_visibility(m, s, sl);
  const auto offsets = sample_offsets(s);
  const int spp = int(offsets.size());
  Verdict v;
  for (int j = 0; j < c.height; ++j)
    for (int i = 0; i < c.width; ++i) {
      const float *pa = a.pixel(i, j), *pb = b.pixel(i, j);
      Outcome out;
      for (int k = 0; k < 3; ++k) out.err = std::max(out.err, double(std::abs(pa[k] - pb[k])));
      if (!(out.err <= 1.0 / 255)) {
        bool tie = false;
        for (int k = 0; k < spp; ++k) {
          const size_t x = (size_t(j) * c.width + i) * spp + k;
          const int64_t px = int64_t(i) * kSubpixel + offsets[k][0],
                        py = int64_t(j) * kSubpixel + offsets[k][1];
          if (zb.tri[x] != Visibility::kNone && sl.tri[x] != Visibility::kNone &&
              zb.tri[x] != sl.tri[x] &&
              depth_tie(s.depth, exact_depth(m, s, zb.tri[x], px, py),
                        exact_depth(m, s, sl.tri[x], px, py)))
            tie = true;
        }
        out.kind = tie ? Outcome::explained : Outcome::unexplained;
        out.label = tie ? "depth_tie" : "differs";
        std::ostringstream d;
        d << "pixel (" << i << ", " << j << "): scanline " << impl.name << " (" << pa[0] << ", "
          << pa[1] << ", " << pa[2] << ") vs zbuffer reference (" << pb[0] << ", " << pb[1] << ", "
          << pb[2] << "), error " << out.err;
        out.detail = d.str();
      } else {
        out.measured = true;
      }
      v.rays.push_back(out);
    }
  return v;
}

Property frame_property(const Family& family, const FamilyImpl& impl) {
  Property p;
  p.family = std::string(family.name);
  p.check = "scanline_equals_zbuffer";
  p.suite = "ScanlineEqualsZbuffer";
  p.name = std::string(family.name) + "__" + std::string(impl.name);
  p.generator = "triangle_soup";
  p.pair = std::string(family.name);
  p.impl = std::string(impl.name);
  p.bound = 1.0 / 255;
  p.unit = "colour";
  p.units = "pixels";
  const auto gen = std::make_shared<const rc::Gen<RasterCase>>(triangle_soup());
  p.run = [gen, &impl] {
    auto c = std::make_shared<RasterCase>(**gen);
    Ran r;
    r.verdict = check_frame(impl, *c);
    r.text = [c](long) { return write_case(*c); };
    return r;
  };
  p.replay = [&impl](const std::string& text, const std::string& file) {
    return check_frame(impl, read_case(text, file));
  };
  return p;
}

}  // namespace

void scanline_part(const Family& family, FamilyProperties& out) {
  for (const FamilyImpl& impl : family.impls) {
    if (VisibilityFn scan = visibility_of(impl.name))
      out.properties.push_back(coverage_property(family, std::string(impl.name), scan));
    else
      out.fixed.push_back(
          {"ScanlineCoverage", std::string(family.name) + "__" + std::string(impl.name),
           [name = std::string(impl.name)] {
             FAIL() << "scanline implementation " << name
                    << " has no visibility pass in props/raster/scanline.cpp (visibility_of)";
           }});
    out.properties.push_back(frame_property(family, impl));
  }
  for (const CoverageMutant& m : coverage_mutants())
    out.mutants.push_back(
        {m.name, m.what, "scanline_coverage", {coverage_property(family, m.name, m.fn)}});
}

}  // namespace lockstep::props::raster

// lockstep props/marching_cubes: the checks and the fixed tests (see checks.h).
#include "props/marching_cubes/checks.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <set>
#include <tuple>
#include <vector>

#include "core/marching_cubes.h"
#include "kinds/mesh_kind.h"
#include "props/gen/case_text.h"
#include "props/marching_cubes/generators.h"
#include "props/marching_cubes/oracle.h"
#include "props/property.h"

namespace lockstep::props::marching_cubes {

using gen::hex;

namespace {

Mesh run(const FamilyImpl& impl, const McCase& c) {
  FrameOptions o;
  o.threads = 1;
  o.params.set("iso", hex(c.iso));
  Input in = make_input<Volume>(c.volume, c.volume.source, 0, 0);
  return impl.run_as<Mesh>(in, o, nullptr);
}

std::string pos(const Vec3f& v) {
  char buf[120];
  std::snprintf(buf, sizeof buf, "(%a, %a, %a)", double(v.x), double(v.y), double(v.z));
  return buf;
}

// Triangles as position triples, each rotated to start at its least position:
// the same oriented triangle in any listing.
using Tri = std::array<std::tuple<float, float, float>, 3>;
std::multiset<Tri> triangle_set(const Mesh& m) {
  std::multiset<Tri> out;
  for (const auto& t : m.triangles) {
    Tri q;
    for (int k = 0; k < 3; ++k) {
      const Vec3f& v = m.vertices[t[size_t(k)]];
      q[size_t(k)] = {v.x + 0.0f, v.y + 0.0f, v.z + 0.0f};
    }
    while (!(q[0] <= q[1] && q[0] <= q[2])) std::rotate(q.begin(), q.begin() + 1, q.end());
    out.insert(q);
  }
  return out;
}

}  // namespace

Verdict agreement(const FamilyImpl& ref, const FamilyImpl& impl, const McCase& c) {
  const Mesh a = weld(run(ref, c)), b = weld(run(impl, c));
  Outcome o;
  const auto ta = triangle_set(a), tb = triangle_set(b);
  std::set<std::tuple<float, float, float>> va, vb;
  for (const Vec3f& v : a.vertices) va.insert({v.x + 0.0f, v.y + 0.0f, v.z + 0.0f});
  for (const Vec3f& v : b.vertices) vb.insert({v.x + 0.0f, v.y + 0.0f, v.z + 0.0f});
  if (ta != tb || va != vb) {
    o.kind = Outcome::unexplained;
    o.label = "differs";
    std::ostringstream d;
    d << "reference " << a.triangles.size() << " triangles, " << a.vertices.size() << " vertices; " << impl.name << " "
      << b.triangles.size() << " triangles, " << b.vertices.size() << " vertices (welded)";
    std::vector<Tri> only_a, only_b;
    std::set_difference(ta.begin(), ta.end(), tb.begin(), tb.end(), std::back_inserter(only_a));
    std::set_difference(tb.begin(), tb.end(), ta.begin(), ta.end(), std::back_inserter(only_b));
    auto show = [](const Tri& t) {
      std::string s;
      for (const auto& [x, y, z] : t) s += pos(Vec3f(x, y, z)) + " ";
      return s;
    };
    d << "; " << only_a.size() << " triangles only in the reference";
    if (!only_a.empty()) d << " (first: " << show(only_a.front()) << ")";
    d << ", " << only_b.size() << " only in " << impl.name;
    if (!only_b.empty()) d << " (first: " << show(only_b.front()) << ")";
    o.detail = d.str();
  }
  Verdict v;
  v.rays.push_back(o);
  return v;
}

namespace {

// Faces of the volume's cubes whose corners alternate below / not below around
// the face (two below corners on one diagonal): where a table may keep the
// below corners apart (ours, always) or join them (the other separation).
long ambiguous_faces(const Volume& v, double iso) {
  auto below = [&](int i, int j, int k) { return double(v.at(i, j, k)) < iso; };
  long n = 0;
  // A face spanned by axes a and b at sample (i, j, k): corners p, p+a, p+a+b, p+b.
  auto face = [&](int i, int j, int k, int ai, int aj, int ak, int bi, int bj, int bk) {
    const bool c0 = below(i, j, k), c1 = below(i + ai, j + aj, k + ak),
               c2 = below(i + ai + bi, j + aj + bj, k + ak + bk), c3 = below(i + bi, j + bj, k + bk);
    n += c0 == c2 && c1 == c3 && c0 != c1;
  };
  for (int k = 0; k < v.nz; ++k)
    for (int j = 0; j < v.ny; ++j)
      for (int i = 0; i < v.nx; ++i) {
        if (i + 1 < v.nx && j + 1 < v.ny) face(i, j, k, 1, 0, 0, 0, 1, 0);
        if (i + 1 < v.nx && k + 1 < v.nz) face(i, j, k, 1, 0, 0, 0, 0, 1);
        if (j + 1 < v.ny && k + 1 < v.nz) face(i, j, k, 0, 1, 0, 0, 0, 1);
      }
  return n;
}

// The largest |coordinate| of the volume's corners: the scale of a float's
// rounding of any cut point.
double coordinate_scale(const Volume& v) {
  double m = 0;
  for (int c = 0; c < 8; ++c) {
    const Vec3 p = v.position(mc::corner_x(c) * (v.nx - 1), mc::corner_y(c) * (v.ny - 1), mc::corner_z(c) * (v.nz - 1));
    m = std::max({m, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
  }
  return m;
}

}  // namespace

// A peer's surface against the reference's (PeerAgrees, above).
Verdict peer_agrees(const FamilyImpl& ref, const FamilyImpl& impl, const McCase& c, bool judge_topology) {
  // On ties (PeerVertices) the peer puts a cut point on the sample that equals
  // iso, as the interpolation alone does; ours is kTieOffset of the edge from
  // it (core/marching_cubes.h, rule 2): compared with the rule undone.
  const Mesh a = weld(judge_topology ? run(ref, c) : ties_on_samples(run(ref, c), c.volume, c.iso)),
             b = weld(run(impl, c));
  const Topology ta = topology(a), tb = topology(b);
  const long ambiguous = ambiguous_faces(c.volume, c.iso);
  Outcome o;
  o.cls = ambiguous > 0 ? "ambiguous" : "unambiguous";
  // Two-sided: every vertex of either welded mesh to the other's nearest, in
  // units of the coordinates' scale (core/marching_cubes.h: cut points are
  // rounded to float once; VTK's to float too, by its own arithmetic).
  double worst = 0;
  if (a.vertices.empty() != b.vertices.empty()) worst = kInfinity;
  else if (!a.vertices.empty())
    for (const auto& d : {nearest_vertex_distance(a, b), nearest_vertex_distance(b, a)})
      for (double x : d) worst = std::max(worst, std::isnan(x) ? kInfinity : x);
  const double scale = std::max(coordinate_scale(c.volume), 1e-300);
  o.err = worst / scale;
  o.measured = std::isfinite(o.err);
  auto same = [](const Topology& x, const Topology& y) {
    return x.euler() == y.euler() && x.components == y.components && x.closed_manifold() == y.closed_manifold() &&
           x.boundary_edges == y.boundary_edges;
  };
  const bool same_topology = same(ta, tb);
  // The other separation on every ambiguous face: our table on -f at -iso
  // (its below corners are our corners >= iso).
  McCase neg = c;
  for (float& x : neg.volume.data) x = -x;
  neg.iso = std::nextafter(-c.iso, kInfinity);
  const Topology tn = topology(weld(run(ref, neg)));
  const bool dual = same(tn, tb);
  std::ostringstream d;
  d << "iso " << hex(c.iso) << ", " << ambiguous << " ambiguous faces; reference " << ta.str() << "; " << impl.name
    << " " << tb.str() << "; worst vertex distance " << worst << " (" << o.err << " of the coordinates' scale "
    << scale << ", bound " << kPeerVertexBound << "); reference on -f " << tn.str() << (dual ? " (same)" : " (differs)");
  o.detail = d.str();
  if (!(o.err <= kPeerVertexBound)) {
    o.kind = Outcome::unexplained;
    o.label = "vertices_differ";
  } else if (judge_topology && (ambiguous == 0 ? !same_topology : !dual)) {
    // Without an ambiguous face both tables must give our topology; with one,
    // the peer's must be exactly that of the other separation.
    o.kind = Outcome::unexplained;
    o.label = ambiguous == 0 ? "topology_differs" : "not_the_other_separation";
  } else if (judge_topology && !same_topology) {
    o.kind = Outcome::explained;
    o.label = known_label(std::string(impl.name), impl.known);
  }
  Verdict v;
  v.rays.push_back(o);
  return v;
}

namespace {

// Signed volume enclosed (divergence theorem): positive when the normals point out.
double enclosed_volume(const Mesh& m) {
  double vol = 0;
  for (const auto& t : m.triangles) {
    const Vec3f &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
    vol += dot(Vec3{a.x, a.y, a.z}, cross(Vec3{b.x, b.y, b.z}, Vec3{c.x, c.y, c.z})) / 6;
  }
  return vol;
}

}  // namespace

// The mesh with the tie rule undone (core/marching_cubes.h, rule 2): every
// cut point the rule moved off a sample put back where the interpolation
// alone puts it (on the sample). What VTK computes, and the mutant
// ties_on_samples.
Mesh ties_on_samples(Mesh m, const Volume& v, double iso) {
  std::map<std::tuple<float, float, float>, Vec3f> back;
  for (int k = 0; k < v.nz; ++k)
    for (int j = 0; j < v.ny; ++j)
      for (int i = 0; i < v.nx; ++i)
        for (int axis = 0; axis < 3; ++axis) {
          const int i1 = i + (axis == 0), j1 = j + (axis == 1), k1 = k + (axis == 2);
          if (i1 >= v.nx || j1 >= v.ny || k1 >= v.nz) continue;
          const double fa = v.at(i, j, k), fb = v.at(i1, j1, k1);
          if ((fa < iso) == (fb < iso)) continue;
          const Vec3 a = v.position(i, j, k), b = v.position(i1, j1, k1);
          const Vec3f moved = mc::cut_point(a, b, fa, fb, iso), plain = mc::interpolated_point(a, b, fa, fb, iso);
          if (!(moved == plain)) back[{moved.x, moved.y, moved.z}] = plain;
        }
  for (Vec3f& p : m.vertices)
    if (const auto it = back.find({p.x, p.y, p.z}); it != back.end()) p = it->second;
  return m;
}

namespace {

// What ClosedAtTies and TiesHandMade measure of a mesh as produced.
struct TieFigures {
  size_t triangles = 0, zero_area = 0;
  Topology welded;
  std::string first_bad;  // the first zero-area triangle or bad welded edge, as positions
  bool clean() const { return zero_area == 0 && welded.closed_manifold(); }
  std::string str() const {
    return std::to_string(triangles) + " triangles, " + std::to_string(zero_area) + " of zero area; welded " +
           welded.str() + (first_bad.empty() ? "" : "; first: " + first_bad);
  }
};

TieFigures tie_figures(const Mesh& m) {
  TieFigures f;
  f.triangles = m.triangles.size();
  f.zero_area = zero_area_triangles(m);
  const Mesh w = weld(m);
  f.welded = topology(w);
  for (const auto& t : m.triangles) {
    if (!f.first_bad.empty()) break;
    Mesh one;
    one.vertices = {m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]};
    one.triangles = {{0, 1, 2}};
    if (zero_area_triangles(one)) f.first_bad = "zero-area triangle " + pos(one.vertices[0]) + " " + pos(one.vertices[1]) + " " + pos(one.vertices[2]);
  }
  if (f.first_bad.empty()) {
    // An edge of the welded mesh not run once each way by exactly two triangles.
    std::map<std::pair<uint32_t, uint32_t>, int> runs;  // (a, b) a -> b
    for (const auto& t : w.triangles)
      for (int k = 0; k < 3; ++k) ++runs[{t[size_t(k)], t[size_t(k + 1) % 3]}];
    for (const auto& [e, n] : runs) {
      const auto back = runs.find({e.second, e.first});
      const int other = back == runs.end() ? 0 : back->second;
      if (n != 1 || other != 1) {
        f.first_bad = "edge " + pos(w.vertices[e.first]) + " -> " + pos(w.vertices[e.second]) + " run " +
                      std::to_string(n) + " times that way and " + std::to_string(other) + " the other";
        break;
      }
    }
  }
  return f;
}

}  // namespace

// ClosedAtTies: the implementation's mesh as produced has no zero-area
// triangle, and welded by position it is a closed oriented 2-manifold
// enclosing volume of the right sign (closed()); the reference's figures on
// the same case are printed beside its own.
Verdict closed_at_ties(const FamilyImpl& ref, const FamilyImpl& impl, const McCase& c, int border) {
  const Mesh m = run(impl, c);
  const TieFigures f = tie_figures(m);
  long equal = 0;
  for (float x : c.volume.data) equal += double(x) == c.iso;
  Verdict v = closed(impl, c, border, false);
  Outcome& o = v.rays.front();
  if (!f.clean() || !v.passed()) {
    o.kind = Outcome::unexplained;
    o.label = f.zero_area ? "zero_area" : "not_manifold_welded";
    const TieFigures r = &impl == &ref ? f : tie_figures(run(ref, c));
    o.detail = "iso " + hex(c.iso) + " (" + std::to_string(equal) + " samples equal it): " + std::string(impl.name) +
               " " + f.str() + (o.detail.empty() ? "" : " (" + o.detail + ")") + "; reference " + r.str();
  }
  return v;
}

// border > 0: the inside is below (the volume must come out positive); < 0 the reverse.
Verdict closed(const FamilyImpl& impl, const McCase& c, int border, bool spheres) {
  const Mesh m = weld(run(impl, c));
  const Topology t = topology(m);
  Outcome o;
  std::string why;
  if (!t.closed_manifold()) why = "not a closed oriented manifold";
  else if (t.euler() % 2 != 0) why = "odd Euler characteristic";
  else if (spheres && t.euler() != 2 * t.components) why = "a component is not a sphere (chi != 2 per component)";
  const double vol = enclosed_volume(m);
  if (why.empty() && !m.triangles.empty() && !(border > 0 ? vol > 0 : vol < 0))
    why = "encloses volume " + hex(vol) + " (normals point the wrong way)";
  if (!why.empty()) {
    o.kind = Outcome::unexplained;
    o.label = "open_or_misoriented";
    o.detail = why + ": " + t.str() + "; iso " + hex(c.iso);
  }
  Verdict v;
  v.rays.push_back(o);
  return v;
}

// ---------------------------------------------------------------- fixed tests

void single_cubes(const FamilyImpl& impl) {
  int failures = 0;
  for (int bits = 0; bits < 256; ++bits)
    for (bool complement : {false, true}) {
      const McCase c = single_cube(bits, complement);
      const Verdict v = closed(impl, c, complement ? -1 : 1, true);
      if (!v.passed() && ++failures <= 5) ADD_FAILURE() << c.volume.source << ": " << v.first_failure() << "\n" << write_case(c);
    }
  EXPECT_EQ(failures, 0) << "configurations whose surface is not closed, oriented and made of spheres";
}

// Two-sided Hausdorff distance to the sphere |p| = kR (oracle.h), against h:
// c = distance R / h^2 over four halvings of h (h = 2/8 ... 2/128), each
// within 10% of the five's mean.
void sphere_convergence(const FamilyImpl& impl) {
  constexpr double kR = 0.6;
  std::vector<double> ratio;
  std::string table;
  for (int n : {9, 17, 33, 65, 129}) {
    McCase c;
    Volume& v = c.volume;
    v.nx = v.ny = v.nz = n;
    const double h = 2.0 / (n - 1);
    v.spacing = {h, h, h};
    v.origin = {-1, -1, -1};
    v.data.resize(size_t(n) * n * n);
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) v.at(i, j, k) = float(length(v.position(i, j, k)));
    c.iso = kR;
    const Hausdorff d = sphere_hausdorff(run(impl, c), kR, h / 2);
    ratio.push_back(d.two_sided() / (h * h) * kR);
    char buf[200];
    std::snprintf(buf, sizeof buf,
                  "  h %.5f  mesh->sphere %.3e  sphere->mesh %.3e  two-sided %.3e  c = distance R / h^2 = %.4f\n", h,
                  d.mesh_to_surface, d.surface_to_mesh, d.two_sided(), ratio.back());
    table += buf;
  }
  std::cout << "[ lockstep ] sphere R " << kR << ", two-sided Hausdorff distance against h:\n" << table;
  double mean = 0;
  for (double r : ratio) mean += r / double(ratio.size());
  for (size_t i = 0; i < ratio.size(); ++i)
    EXPECT_NEAR(ratio[i], mean, 0.1 * mean) << "distance / h^2 does not settle (grid " << i << ")\n" << table;
}

// TiesHandMade: on hand_made_ties(), our implementations' meshes have no
// zero-area triangle and weld into a closed oriented 2-manifold; the same
// meshes with the tie rule undone (on the samples, what the interpolation
// alone gives) must not (the field exercises the rule). A peer's figures are
// printed, not judged (VTK puts cut points on samples).
void ties_hand_made(const FamilyImpl& ref, const FamilyImpl& impl) {
  const McCase c = hand_made_ties();
  long equal = 0;
  for (float x : c.volume.data) equal += double(x) == c.iso;
  const Mesh m = run(impl, c);
  const TieFigures f = tie_figures(m);
  std::cout << "[ lockstep ] " << c.volume.source << " (" << c.volume.nx << "x" << c.volume.ny << "x" << c.volume.nz
            << ", iso 2, " << equal << " samples equal it): " << impl.name << " " << f.str() << "\n";
  if (!impl.peer.empty()) {
    std::cout << "[ lockstep ] " << impl.name << " is a peer: measured, not judged\n";
    return;
  }
  const TieFigures undone = tie_figures(ties_on_samples(m, c.volume, c.iso));
  std::cout << "[ lockstep ]   with the tie rule undone: " << undone.str() << "\n";
  EXPECT_TRUE(f.clean()) << impl.name << " on the " << c.volume.source << ": " << f.str() << "\nreference "
                         << tie_figures(run(ref, c)).str() << "\n" << write_case(c);
  EXPECT_GT(undone.zero_area, 0u) << "the field does not put cut points on samples\n" << write_case(c);
  EXPECT_GT(undone.welded.nonmanifold_edges, 0) << "the field does not pinch the welded mesh\n" << write_case(c);
  const Verdict v = closed(impl, c, -1, false);
  EXPECT_TRUE(v.passed()) << v.first_failure() << "\n" << write_case(c);
}

}  // namespace lockstep::props::marching_cubes

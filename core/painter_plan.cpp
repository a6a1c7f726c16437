// lockstep core: the painter's plan (core/painter_plan.h): the NNS tests, the
// must-draw-before graph and its order, shared by every painter row; the
// reference's frame is reference/painter.cpp.
//
// Method (Newell, Newell and Sancha 1972; Foley et al., 2nd ed., 15.5.1):
//   1. Depth sort: every triangle by its farthest eye depth, back to front.
//   2. For each pair whose screen extents overlap, decide whether it needs an
//      order, and which, with the NNS tests in their textbook order
//      (classify_pair). Each answer "p must be drawn before q" is an edge of the
//      must-draw-before graph. NNS splits a polygon when every test fails; we
//      instead find out exactly what the pair is: interpenetrating (an exact
//      triangle-triangle intersection test) or in a definite order (the depth
//      difference at one point of their common screen area).
//   3. The strongly connected components of that graph (Tarjan 1972): a
//      component with more than one triangle is a cycle, which no order draws
//      right. Interpenetrating pairs join their two triangles' components.
//   4. Draw the components in a topological order of the component graph
//      (Kahn 1962), the earliest in the depth sort first; inside a component the
//      triangles go in depth-sort order -- or, with settings.split, each sample
//      goes to the component's triangle in front at that sample: the component
//      split along its triangles' planes as finely as the samples can see.
//   Every triangle fills its samples with the z-buffer's fill rule, sample
//   positions and shade_fragment, so that a right order gives the z-buffer's
//   image, sample for sample.
#include "core/painter_plan.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

#include "core/error.h"

namespace lockstep {

namespace {



// Which side of the plane of t the point v lies on: +1 in front (larger W, nearer),
// -1 behind, 0 on it. t has positive screen area, so orient3d's sign flips.
int side(const PainterTri& t, const Vec3& v) {
  // A vertex of t lies on its plane (mesh neighbours share vertices: this is
  // the common case, and one the floating-point filter can never decide).
  if (v == t.s[0] || v == t.s[1] || v == t.s[2]) return 0;
  return -exact::orient3d(t.s[0], t.s[1], t.s[2], v);
}

// Point (x, y) in the closed screen triangle t.
bool in_closed(const PainterTri& t, int64_t x, int64_t y) {
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    if (edge_function(t.x[i], t.y[i], t.x[j], t.y[j], x, y) < 0) return false;
  }
  return true;
}

int sgn(int64_t v) { return (v > 0) - (v < 0); }

// The order of two triangles that do not meet and whose projections overlap:
// their depth difference D = W_q - W_p has one sign over the common screen area,
// so its sign at any point of that area decides. The points tried are the
// corners of the common area: vertices of one inside the other, and proper
// crossings of edges. 0 when every corner has D = 0 (they touch there).
int witness_sign(const PainterTri& p, const PainterTri& q) {
  // A vertex of p over q: D < 0 when p's vertex is in front of q's plane.
  for (int i = 0; i < 3; ++i)
    if (in_closed(q, p.x[i], p.y[i]))
      if (const int s = side(q, p.s[i]); s != 0) return -s;
  // A vertex of q over p.
  for (int i = 0; i < 3; ++i)
    if (in_closed(p, q.x[i], q.y[i]))
      if (const int s = side(p, q.s[i]); s != 0) return s;
  // Two edges crossing: q's edge is above p's at the crossing iff q's second
  // endpoint is above the plane through p's edge and q's first endpoint.
  for (int i = 0; i < 3; ++i) {
    const int i2 = (i + 1) % 3;
    for (int k = 0; k < 3; ++k) {
      const int k2 = (k + 1) % 3;
      const int64_t o1 = edge_function(p.x[i], p.y[i], p.x[i2], p.y[i2], q.x[k], q.y[k]);
      const int64_t o2 = edge_function(p.x[i], p.y[i], p.x[i2], p.y[i2], q.x[k2], q.y[k2]);
      const int64_t o3 = edge_function(q.x[k], q.y[k], q.x[k2], q.y[k2], p.x[i], p.y[i]);
      const int64_t o4 = edge_function(q.x[k], q.y[k], q.x[k2], q.y[k2], p.x[i2], p.y[i2]);
      if (sgn(o1) * sgn(o2) >= 0 || sgn(o3) * sgn(o4) >= 0) continue;  // not a proper crossing
      const int s = -exact::orient3d(p.s[i], p.s[i2], q.s[k], q.s[k2]) * sgn(o1);
      if (s != 0) return s;
    }
  }
  return 0;
}

// Tarjan's strongly connected components, iteratively (scenes have long chains).
// Returns the component of each vertex; components are numbered in reverse
// topological order of the component graph.
std::vector<uint32_t> tarjan(const std::vector<std::vector<uint32_t>>& adj, uint32_t& count) {
  const uint32_t n = uint32_t(adj.size());
  constexpr uint32_t kUnseen = std::numeric_limits<uint32_t>::max();
  std::vector<uint32_t> index(n, kUnseen), low(n, 0), comp(n, kUnseen);
  std::vector<uint32_t> stack;
  std::vector<uint8_t> on_stack(n, 0);
  std::vector<std::pair<uint32_t, uint32_t>> call;  // (vertex, next edge to look at)
  uint32_t next_index = 0;
  count = 0;
  for (uint32_t root = 0; root < n; ++root) {
    if (index[root] != kUnseen) continue;
    call.push_back({root, 0});
    index[root] = low[root] = next_index++;
    stack.push_back(root);
    on_stack[root] = 1;
    while (!call.empty()) {
      auto& [v, e] = call.back();
      if (e < adj[v].size()) {
        const uint32_t w = adj[v][e++];
        if (index[w] == kUnseen) {  // tree edge: descend
          index[w] = low[w] = next_index++;
          stack.push_back(w);
          on_stack[w] = 1;
          call.push_back({w, 0});
        } else if (on_stack[w]) {
          low[v] = std::min(low[v], index[w]);
        }
        continue;
      }
      // v is finished: a root of a component pops it.
      const uint32_t done = v;
      call.pop_back();
      if (!call.empty()) low[call.back().first] = std::min(low[call.back().first], low[done]);
      if (low[done] == index[done]) {
        uint32_t w;
        do {
          w = stack.back();
          stack.pop_back();
          on_stack[w] = 0;
          comp[w] = count;
        } while (w != done);
        ++count;
      }
    }
  }
  return comp;
}

}  // namespace

// ---------------------------------------------------------------- per triangle

PainterTri painter_tri(const ScreenTri& t) {
  PainterTri p;
  p.zmin = kInfinity;
  p.zmax = -kInfinity;
  for (int i = 0; i < 3; ++i) {
    p.x[i] = t.v[i].x;
    p.y[i] = t.v[i].y;
    // The depth the z-buffer interpolates linearly on screen, larger = nearer.
    const double w = 1.0 / t.v[i].z;
    p.s[i] = Vec3(double(p.x[i]), double(p.y[i]), w);
    p.zmin = std::min(p.zmin, t.v[i].z);
    p.zmax = std::max(p.zmax, t.v[i].z);
  }
  p.xmin = std::min({p.x[0], p.x[1], p.x[2]});
  p.xmax = std::max({p.x[0], p.x[1], p.x[2]});
  p.ymin = std::min({p.y[0], p.y[1], p.y[2]});
  p.ymax = std::max({p.y[0], p.y[1], p.y[2]});
  p.area = edge_function(p.x[0], p.y[0], p.x[1], p.y[1], p.x[2], p.y[2]);
  return p;
}

// ---------------------------------------------------------------- one pair

// Whether the interiors of the two screen triangles are disjoint: some edge of
// one has the whole other triangle on its outer side or on it (separating axis).
bool projections_disjoint(const PainterTri& p, const PainterTri& q) {
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    bool q_out = true, p_out = true;
    for (int k = 0; k < 3; ++k) {
      q_out = q_out && edge_function(p.x[i], p.y[i], p.x[j], p.y[j], q.x[k], q.y[k]) <= 0;
      p_out = p_out && edge_function(q.x[i], q.y[i], q.x[j], q.y[j], p.x[k], p.y[k]) <= 0;
    }
    if (q_out || p_out) return true;
  }
  return false;
}

PairVerdict classify_pair(const PainterTri& p, const PainterTri& q) {
  // Tests 1 and 2: screen extents disjoint in x, in y (touching counts: no
  // sample is inside both, the fill rule gives a shared boundary to one).
  if (p.xmax <= q.xmin || q.xmax <= p.xmin) return {PairOrder::kNone, 1};
  if (p.ymax <= q.ymin || q.ymax <= p.ymin) return {PairOrder::kNone, 2};
  // Where each triangle's vertices lie against the other's plane.
  int p_vs_q[3], q_vs_p[3];
  for (int i = 0; i < 3; ++i) {
    p_vs_q[i] = side(q, p.s[i]);
    q_vs_p[i] = side(p, q.s[i]);
  }
  const bool coplanar = p_vs_q[0] == 0 && p_vs_q[1] == 0 && p_vs_q[2] == 0;
  const bool p_behind_q = p_vs_q[0] <= 0 && p_vs_q[1] <= 0 && p_vs_q[2] <= 0;
  const bool q_front_p = q_vs_p[0] >= 0 && q_vs_p[1] >= 0 && q_vs_p[2] >= 0;
  const bool q_behind_p = q_vs_p[0] <= 0 && q_vs_p[1] <= 0 && q_vs_p[2] <= 0;
  const bool p_front_q = p_vs_q[0] >= 0 && p_vs_q[1] >= 0 && p_vs_q[2] >= 0;
  // The order tests say which order would be right where they overlap; an
  // order is only a constraint where the projections share interior (test 5).
  PairVerdict v{PairOrder::kNone, 0};
  if (coplanar)
    v = {PairOrder::kCoplanar, 3};
  else if (p.zmin >= q.zmax)
    v = {PairOrder::kPFirst, 0};  // p wholly farther
  else if (q.zmin >= p.zmax)
    v = {PairOrder::kQFirst, 0};
  else if (p_behind_q)
    v = {PairOrder::kPFirst, 3};  // test 3
  else if (q_front_p)
    v = {PairOrder::kPFirst, 4};  // test 4
  else if (q_behind_p || p_front_q)
    v = {PairOrder::kQFirst, 6};  // the reversed tests: swap
  // Test 5: projections disjoint (exact, on the snapped screen triangles).
  if (projections_disjoint(p, q)) return {PairOrder::kNone, 5};
  if (v.test != 0 || v.order != PairOrder::kNone) return v;
  // Every test failed: each straddles the other's plane. Either they cross
  // (interpenetration) or one is in front over all of their common area.
  if (exact::triangles_intersect(p.s, q.s)) return {PairOrder::kInterpenetrate, 7};
  const int d = witness_sign(p, q);
  if (d > 0) return {PairOrder::kPFirst, 8};
  if (d < 0) return {PairOrder::kQFirst, 8};
  return {PairOrder::kInterpenetrate,
          8};  // cannot happen for disjoint triangles; be safe and report
}

bool nearer_at(const PainterTri& a, uint32_t ia, const PainterTri& b, uint32_t ib, int64_t sx,
               int64_t sy) {
  // W_a(s) = sum_i W_ai e_ai(s) / A_a, likewise for b. Compare the cross-multiplied
  // numerators exactly: sum_i W_ai e_ai A_b - sum_i W_bi e_bi A_a.
  double rows[6][3];
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    const int64_t ea = edge_function(a.x[j], a.y[j], a.x[k], a.y[k], sx, sy);
    const int64_t eb = edge_function(b.x[j], b.y[j], b.x[k], b.y[k], sx, sy);
    rows[i][0] = a.s[i].z;
    rows[i][1] = double(ea);
    rows[i][2] = double(b.area);
    rows[3 + i][0] = -b.s[i].z;
    rows[3 + i][1] = double(eb);
    rows[3 + i][2] = double(a.area);
  }
  const int s = exact::sign_of_triple_products(rows, 6);
  return s > 0 || (s == 0 && ia < ib);
}

// ---------------------------------------------------------------- the plan

std::vector<uint32_t> painter_sort(const std::vector<PainterTri>& tris) {
  // Farthest first; equal keys keep scene order.
  std::vector<uint32_t> sorted(tris.size());
  for (uint32_t i = 0; i < sorted.size(); ++i) sorted[i] = i;
  std::stable_sort(sorted.begin(), sorted.end(),
                   [&](uint32_t a, uint32_t b) { return tris[a].zmax > tris[b].zmax; });
  return sorted;
}

std::vector<PairFinding> painter_pairs(const std::vector<PainterTri>& tris,
                                       const std::vector<uint32_t>& sorted) {
  const uint32_t n = uint32_t(tris.size());
  std::vector<uint32_t> pos(n);
  for (uint32_t i = 0; i < n; ++i) pos[sorted[i]] = i;
  // A sweep along x: only pairs whose x extents overlap are looked at (test 1
  // for all the others), sorted by their left ends.
  std::vector<uint32_t> by_x(n);
  for (uint32_t i = 0; i < n; ++i) by_x[i] = i;
  std::sort(by_x.begin(), by_x.end(), [&](uint32_t a, uint32_t b) {
    return tris[a].xmin != tris[b].xmin ? tris[a].xmin < tris[b].xmin : a < b;
  });
  std::vector<PairFinding> out;
  for (uint32_t a = 0; a < n; ++a) {
    const PainterTri& ta = tris[by_x[a]];
    for (uint32_t b = a + 1; b < n && tris[by_x[b]].xmin < ta.xmax; ++b) {
      uint32_t ip = by_x[a], iq = by_x[b];
      if (pos[iq] < pos[ip]) std::swap(ip, iq);  // p: the one the sort draws first
      const PairVerdict v = classify_pair(tris[ip], tris[iq]);
      if (v.test == 1 || v.test == 2)
        continue;  // extents disjoint (in y: x overlaps, by the sweep)
      out.push_back({ip, iq, v});
    }
  }
  return out;
}

PainterPlan painter_plan(const std::vector<PainterTri>& tris) {
  std::vector<uint32_t> sorted = painter_sort(tris);
  const std::vector<PairFinding> pairs = painter_pairs(tris, sorted);
  return painter_plan(tris, std::move(sorted), pairs);
}

PainterPlan painter_plan(const std::vector<PainterTri>& tris, std::vector<uint32_t> sorted,
                         const std::vector<PairFinding>& pairs) {
  PainterPlan plan;
  const uint32_t n = uint32_t(tris.size());
  plan.sorted = std::move(sorted);
  std::vector<uint32_t> pos(n);
  for (uint32_t i = 0; i < n; ++i) pos[plan.sorted[i]] = i;

  // 2. The must-draw-before graph from the pairs' verdicts (order_adj), and the
  // same with interpenetrating pairs tied both ways (group_adj).
  std::vector<std::vector<uint32_t>> order_adj(n), group_adj(n);
  for (const auto& [ip, iq, v] : pairs) {
    ++plan.pairs;
    ++plan.decided_by[v.test];
    switch (v.order) {
      case PairOrder::kNone:
        break;
      case PairOrder::kPFirst:
        order_adj[ip].push_back(iq);
        break;
      case PairOrder::kQFirst:
        order_adj[iq].push_back(ip);
        break;
      case PairOrder::kCoplanar:
        // The z-buffer keeps the first of equal depths: draw the later one first.
        order_adj[std::max(ip, iq)].push_back(std::min(ip, iq));
        plan.coplanar.push_back({std::min(ip, iq), std::max(ip, iq)});
        break;
      case PairOrder::kInterpenetrate:
        group_adj[ip].push_back(iq);
        group_adj[iq].push_back(ip);
        plan.interpenetrations.push_back({std::min(ip, iq), std::max(ip, iq)});
        break;
    }
  }
  // Listed in a canonical order, whatever order the pairs came in.
  std::sort(plan.coplanar.begin(), plan.coplanar.end());
  std::sort(plan.interpenetrations.begin(), plan.interpenetrations.end());
  for (uint32_t i = 0; i < n; ++i) {
    plan.edges += order_adj[i].size();
    group_adj[i].insert(group_adj[i].end(), order_adj[i].begin(), order_adj[i].end());
  }

  // 3. Cycles: components of the must-draw-before graph with more than one triangle.
  uint32_t ncycle = 0;
  const std::vector<uint32_t> cyc = tarjan(order_adj, ncycle);
  std::vector<std::vector<uint32_t>> members(ncycle);
  for (uint32_t t : plan.sorted) members[cyc[t]].push_back(t);
  for (auto& m : members)
    if (m.size() > 1) plan.cycles.push_back(std::move(m));
  std::sort(plan.cycles.begin(), plan.cycles.end(),
            [&](const auto& a, const auto& b) { return pos[a.front()] < pos[b.front()]; });

  // Groups: cycles and interpenetrating pairs together, the units drawn as one.
  uint32_t ngroup = 0;
  plan.group = tarjan(group_adj, ngroup);
  plan.group_size.assign(ngroup, 0);
  for (uint32_t i = 0; i < n; ++i) ++plan.group_size[plan.group[i]];

  // 4. A topological order of the groups (Kahn), earliest in the sort first.
  std::vector<std::vector<uint32_t>> group_members(ngroup);
  for (uint32_t t : plan.sorted) group_members[plan.group[t]].push_back(t);
  for (const auto& m : group_members)
    if (m.size() > 1) plan.groups.push_back(m);
  std::sort(plan.groups.begin(), plan.groups.end(),
            [&](const auto& a, const auto& b) { return pos[a.front()] < pos[b.front()]; });
  std::vector<uint32_t> indegree(ngroup, 0);
  for (uint32_t i = 0; i < n; ++i)
    for (uint32_t j : group_adj[i])
      if (plan.group[i] != plan.group[j]) ++indegree[plan.group[j]];
  using Item = std::pair<uint32_t, uint32_t>;  // (sort position of the group's first member, group)
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> ready;
  for (uint32_t g = 0; g < ngroup; ++g)
    if (indegree[g] == 0) ready.push({pos[group_members[g].front()], g});
  plan.order.reserve(n);
  while (!ready.empty()) {
    const uint32_t g = ready.top().second;
    ready.pop();
    for (uint32_t t : group_members[g]) {
      plan.order.push_back(t);
      for (uint32_t j : group_adj[t])
        if (plan.group[j] != g && --indegree[plan.group[j]] == 0)
          ready.push({pos[group_members[plan.group[j]].front()], plan.group[j]});
    }
  }
  return plan;
}

std::vector<std::string> painter_notes(const ScreenMesh& mesh, const PainterPlan& plan,
                                       bool split) {
  std::vector<std::string> notes;
  if (plan.groups.empty() && plan.coplanar.empty()) return notes;
  const auto tri_name = [&](uint32_t t) {
    return "tri " + std::to_string(t) + " (prim " + std::to_string(mesh.tris[t].prim) + ")";
  };
  size_t in_groups = 0;
  for (const auto& g : plan.groups) in_groups += g.size();
  notes.push_back(
      "painter: " + std::to_string(plan.cycles.size()) + " cycle(s), " +
      std::to_string(plan.interpenetrations.size()) + " interpenetrating pair(s), " +
      std::to_string(plan.coplanar.size()) + " coplanar overlap(s); " + std::to_string(in_groups) +
      " of " + std::to_string(mesh.tris.size()) + " triangles in " +
      std::to_string(plan.groups.size()) + " group(s) that no order draws right; " +
      (split
           ? "split along their planes at every sample they share"
           : "drawn in depth order: where they overlap the image may be wrong (--split resolves)"));
  constexpr size_t kMaxLines = 64;
  size_t lines = 0, left = 0;
  for (const auto& g : plan.groups) {
    if (lines++ >= kMaxLines) {
      ++left;
      continue;
    }
    std::string s = "painter: group of " + std::to_string(g.size()) + " triangles:";
    for (uint32_t t : g) {
      s += ' ';  // not " " + tri_name(t): GCC 12's -Wrestrict misfires on it (a false positive)
      s += tri_name(t);
    }
    notes.push_back(s);
  }
  for (const auto& [a, b] : plan.interpenetrations) {
    if (lines++ >= kMaxLines) {
      ++left;
      continue;
    }
    notes.push_back("painter: interpenetration: " + tri_name(a) + " and " + tri_name(b));
  }
  for (const auto& [a, b] : plan.coplanar) {
    if (lines++ >= kMaxLines) {
      ++left;
      continue;
    }
    notes.push_back("painter: coplanar overlap: " + tri_name(a) + " and " + tri_name(b));
  }
  if (left > 0)
    notes.push_back("painter: ... and " + std::to_string(left) + " more findings not listed");
  return notes;
}

// ---------------------------------------------------------------- one sample

bool painter_covers(const ScreenTri& t, const std::array<int64_t, 3>& e) {
  for (int i = 0; i < 3; ++i) {
    if (e[i] > 0) continue;
    if (e[i] < 0) return false;
    // On the edge opposite vertex i (from v[i+1] to v[i+2]): the top-left rule.
    const ScreenVertex& a = t.v[(i + 1) % 3];
    const ScreenVertex& b = t.v[(i + 2) % 3];
    const int64_t dx = int64_t(b.x) - a.x, dy = int64_t(b.y) - a.y;
    const bool top = dy == 0 && dx > 0;
    const bool left = dy < 0;
    if (!top && !left) return false;
  }
  return true;
}

Fragment painter_fragment(const ScreenMesh& mesh, uint32_t t, int64_t sx, int64_t sy,
                          const std::array<int64_t, 3>& e, int64_t area, bool perspective) {
  // Exactly the z-buffer's arithmetic (reference/zbuffer.cpp), so that the same
  // triangle at the same sample gives the same colour bit for bit.
  const ScreenTri& tri = mesh.tris[t];
  Fragment f;
  f.tri = t;
  f.sx = double(sx) / kSubpixel;
  f.sy = double(sy) / kSubpixel;
  // Screen barycentrics (area ratios), then depth from the plane of 1/z.
  const double l0 = double(e[0]) / double(area), l1 = double(e[1]) / double(area),
               l2 = double(e[2]) / double(area);
  const double inv_z = l0 / tri.v[0].z + l1 / tri.v[1].z + l2 / tri.v[2].z;
  f.z = 1 / inv_z;
  if (perspective) {
    // Perspective-correct: screen barycentrics weighted by 1/z.
    f.b[0] = l0 / tri.v[0].z / inv_z;
    f.b[1] = l1 / tri.v[1].z / inv_z;
    f.b[2] = l2 / tri.v[2].z / inv_z;
  } else {
    f.b[0] = l0;
    f.b[1] = l1;
    f.b[2] = l2;
  }
  return f;
}

}  // namespace lockstep

// lockstep optimized: the simd z-buffer set-up of one sphere (the chunk
// driver, zbuffer_setup.cpp, calls it per sphere): its ring count's unit
// sphere scaled and moved, its vertices projected once, its faces tested a
// vector at a time, its triangles built in place -- view_spheres' and
// Emitter::triangle's arithmetic, operation for operation, so the same bits.
// A sphere with a vertex outside the hither plane or the guard band is left
// to view_scene's own step (view_sphere returns false).
#include <algorithm>
#include <cmath>

#include "optimized/zbuffer/zbuffer_setup.h"

namespace lockstep::opt::zsimd {

// ---------------------------------------------------------------- the unit sphere's faces

UnitFaces unit_faces(const UnitSphere& u) {
  // The UV sphere turns into itself about z by 2 pi / meridians: per band of
  // latitude, meridian 0's faces (one at the poles, two elsewhere, in
  // unit_sphere's order) are worked out, every other meridian's turned from them.
  UnitFaces f;
  const size_t nt = u.tri.size();
  f.nx.resize(nt), f.ny.resize(nt), f.nz.resize(nt), f.h.resize(nt);
  for (int k = 0; k < 3; ++k) {
    f.vertex[k].resize(nt);
    for (size_t t = 0; t < nt; ++t) f.vertex[k][t] = u.tri[t][size_t(k)];
  }
  const int rings = u.rings, meridians = 2 * rings;
  std::vector<double> cos_phi(static_cast<size_t>(meridians)), sin_phi(static_cast<size_t>(meridians));
  for (int l = 0; l < meridians; ++l) {
    cos_phi[size_t(l)] = std::cos(2 * M_PI * l / meridians);
    sin_phi[size_t(l)] = std::sin(2 * M_PI * l / meridians);
  }
  size_t t = 0;
  for (int k = 0; k < rings; ++k) {
    const int per = (k == 0 || k == rings - 1) ? 1 : 2;
    Vec3 n0[2];
    double h0[2] = {0, 0};
    for (int j = 0; j < per; ++j) {
      const auto& [a, b, c] = u.tri[t + size_t(j)];
      const Vec3 n = cross(u.unit[b] - u.unit[a], u.unit[c] - u.unit[a]);
      const double len = length(n);
      n0[j] = len > 0 ? n / len : n;
      h0[j] = dot(n0[j], u.unit[a]);
      if (len > 0) f.inner = std::min(f.inner, std::abs(h0[j]));
    }
    for (int l = 0; l < meridians; ++l) {
      const double cl = cos_phi[size_t(l)], sl = sin_phi[size_t(l)];
      for (int j = 0; j < per; ++j, ++t) {
        f.nx[t] = n0[j].x * cl - n0[j].y * sl;
        f.ny[t] = n0[j].x * sl + n0[j].y * cl;
        f.nz[t] = n0[j].z;
        f.h[t] = h0[j];
      }
    }
  }
  return f;
}

// ---------------------------------------------------------------- one sphere

// Sphere k as view_spheres emits it (unit: its unit sphere), appended to out
// with the counts, when every vertex of its tessellation lies inside the hither
// plane and the guard band (then no triangle is clipped). Otherwise false, and
// nothing is emitted. Operation for operation view_spheres' and Emitter::triangle's
// arithmetic, so the same bits (the vertices and the face tests a vector at a
// time); only the per-triangle copies and the per-sphere sines are gone.
bool view_sphere(const Scene& scene, const RasterSettings& s, const Camera& cam,
                 const Projection& projection, uint32_t k, const UnitSphere& unit,
                 const UnitFaces& unit_face,
                 const ImageOnly* image, const DepthMap& depth_map, const OcclusionMap* occlusion,
                 size_t chunk, FlatBatch& batch, SphereScratch& sc, ScreenMesh& out) {
  const Vec3 c = scene.sphere_center[k];
  const double signed_radius = scene.sphere_radius[k];
  const double r = std::abs(signed_radius);
  const Material& m = scene.materials[scene.sphere_material[k]];
  const FlatBatch::Surface surface(m);
  const bool gouraud = s.shading == Shading::kGouraud, flat_shading = s.shading == Shading::kFlat;
  const size_t nv = unit.unit.size(), nt = unit.tri.size();
  sc.world.resize(nv);
  sc.proj.resize(nv);
  for (size_t i = 0; i < nv; ++i) sc.world[i] = c + r * unit.unit[i];
  // For the image, w and the stored depth too, once per vertex (not per triangle).
  if (image) sc.depth.resize(nv);
  project_vertices(projection, sc.world.data(), nv, sc.proj.data(), image ? &depth_map : nullptr,
                   image ? sc.depth.data() : nullptr);
  for (size_t i = 0; i < nv; ++i)
    if (!sc.proj[i].inside) return false;
  auto normal = [&](uint32_t i) { return signed_radius > 0 ? unit.unit[i] : -unit.unit[i]; };
  if (gouraud) {
    sc.color.resize(nv);
    for (uint32_t i = 0; i < nv; ++i) sc.color[i] = lit(scene, m, cam.eye, sc.world[i], normal(i));
  }
  // Counter-clockwise seen from the visible side: reversed inside out.
  const bool flip = !(signed_radius > 0);
  // Culling in world space: the faces that are back faces by a clear margin,
  // found from the unit sphere's normals (N . (eye - w_a) = n . (eye - c) - r h,
  // n and h the unit face's), are counted and passed over without the world
  // face test; the others get it (sphere_faces, the reference's operations).
  // The margin dwarfs the rounding of c + r u and of the cross product (the
  // unit faces' edges are >= ~1e-4 long, 256 rings), and the sphere must not be
  // so small beside its distance from the origin that its vertices round together.
  // The image's triangles in bulk: positions only (flat shading drawn
  // forward), or with vertex normals for shading (Phong, Blinn-Phong, toon).
  const bool positions = image && image->sink->positions_only();
  const bool shaded = image && !positions && image->sink->shaded_bulk();
  const bool bulk = positions || shaded;
  // The candidates (sc.cand's first nc), and whether they are all front faces
  // by the margin with their vertices in sc.va, vb, vc already (in bulk, when
  // nothing is left to the world face test).
  size_t nc = 0;
  bool all_sure = false;
  const Vec3 e_rel = cam.eye - c;
  const double spread = (length(c) + r) / r;
  // Unit-space normals turned to the drawn side (inside out: reversed).
  const double sign = flip ? -1.0 : 1.0;
  if (s.cull == CullMode::kWorld && spread < 1e6) {
    const double margin = 1e-9 * (length(e_rel) + r) * std::max(1.0, spread);
    // 0: a back face by the margin, 1: either, 2: a front face by the margin;
    // the faces past 0 are the candidates, in order (a vector of faces at a
    // time: sphere_face_codes), those at 2 marked sure for the image: a face
    // that is a front face by the same margin needs no world test either: its
    // unit normal stands in for the world one (the same direction to ~1e-16,
    // far below the image's float shading).
    sc.cand.resize(nt + 16);
    const double e[3] = {e_rel.x, e_rel.y, e_rel.z};
    // In bulk: the candidates' vertices (in the raster's winding) written by
    // the kernel too, for triangle_step.
    FaceVertices verts;
    if (bulk) {
      for (auto* v : {&sc.va, &sc.vb, &sc.vc}) v->resize(nt + 16);
      const auto& vx = unit_face.vertex;
      verts.in[0] = vx[0].data(), verts.in[1] = vx[flip ? 2 : 1].data();
      verts.in[2] = vx[flip ? 1 : 2].data();
      verts.out[0] = sc.va.data(), verts.out[1] = sc.vb.data(), verts.out[2] = sc.vc.data();
    }
    nc = sphere_face_codes(unit_face.nx.data(), unit_face.ny.data(), unit_face.nz.data(),
                           unit_face.h.data(), nt, e, r, sign, margin, image != nullptr,
                           sc.cand.data(), bulk ? &verts : nullptr);
    all_sure = bulk && verts.unsure == 0;
    const uint64_t clear = nt - nc;
    out.sphere_tris += clear;
    out.culled += clear;
  } else {
    sc.cand.resize(nt + 16);
    for (uint32_t t = 0; t < nt; ++t) sc.cand[t] = t;
    nc = nt;
  }
  // (In bulk the sure faces' normals are read from the unit faces and the
  // others' from sphere_faces' results directly, below.)
  if (!bulk) sc.face.resize(3 * nc), sc.flags.resize(nc);
  // The world face test (the reference's operations) on the others.
  sc.cand_tri.resize(nc);
  if (!bulk) sc.amb.resize(nc);  // (bulk: sphere_faces' results are read in order)
  size_t na = 0;
  for (size_t i = 0; i < nc && !all_sure; ++i) {
    const uint32_t t = sc.cand[i] & ~kSureFace;
    if (bulk) {
      if (!(sc.cand[i] & kSureFace)) sc.cand_tri[na++] = unit.tri[t];
    } else if (sc.cand[i] & kSureFace) {
      sc.face[3 * i] = sign * unit_face.nx[t];
      sc.face[3 * i + 1] = sign * unit_face.ny[t];
      sc.face[3 * i + 2] = sign * unit_face.nz[t];
      sc.flags[i] = kFront;
    } else {
      sc.amb[na] = uint32_t(i);
      sc.cand_tri[na++] = unit.tri[t];
    }
  }
  sc.amb_face.resize(3 * na);
  sc.amb_flags.resize(na);
  sphere_faces(sc.world.data(), sc.cand_tri.data(), na, flip, cam.eye, sc.amb_face.data(),
               sc.amb_flags.data());
  for (size_t j = 0; j < na && !bulk; ++j) {
    const size_t i = sc.amb[j];
    for (int k = 0; k < 3; ++k) sc.face[3 * i + size_t(k)] = sc.amb_face[3 * j + size_t(k)];
    sc.flags[i] = sc.amb_flags[j];
  }
  ScreenTri local;
  if (bulk) {
    // The same steps, the area's and the box's in SIMD (triangle_step): the
    // triangles past world culling first, then the kernel, which moves the
    // kept ones to the front and counts the others.
    const size_t room = (nc + 15) / 16 * 16;
    for (auto* v : {&sc.va, &sc.vb, &sc.vc, &sc.vcand}) v->resize(room);
    // Per triangle kept here, where its face normal is (tag): its unit
    // face's index with kSureFace, else its place in sphere_faces' results.
    // (All sure: the candidates themselves, their vertices in place already.)
    size_t n = all_sure ? nc : 0, j = 0;
    uint32_t* const tag = all_sure ? sc.cand.data() : sc.vcand.data();
    if (all_sure) out.sphere_tris += nc;
    for (uint32_t i = 0; i < nc && !all_sure; ++i) {
      const uint32_t ci = sc.cand[i];
      const bool sure = (ci & kSureFace) != 0;
      const uint8_t flags = sure ? kFront : sc.amb_flags[j];
      const uint32_t face_at = sure ? ci : uint32_t(j);
      j += !sure;
      if (flags & kNoFace) continue;
      ++out.sphere_tris;
      if (!(flags & kFront) && s.cull == CullMode::kWorld) {
        ++out.culled;
        continue;
      }
      const auto& [a, b0, c0] = unit.tri[ci & ~kSureFace];
      sc.va[n] = a, sc.vb[n] = flip ? c0 : b0, sc.vc[n] = flip ? b0 : c0;
      sc.vcand[n++] = face_at;
    }
    const size_t padded = (n + 15) / 16 * 16;
    if (n == 0) return true;
    for (auto* v : {&sc.va, &sc.vb, &sc.vc}) std::fill(v->begin() + n, v->begin() + padded, sc.va[0]);
    const OcclusionCells cells = occlusion ? occlusion->cells() : OcclusionCells{};
    TriangleCounts counts;
    const size_t kept = triangle_step(sc.proj.data(), sc.va.data(), sc.vb.data(), sc.vc.data(),
                                      tag, n, image->grid,
                                      s.cull == CullMode::kProjection,
                                      occlusion ? &cells : nullptr, counts);
    out.degenerate += counts.degenerate, out.culled += counts.culled, out.hidden += counts.hidden;
    // Their flat colours' inputs, written straight into the batch's planes
    // (indices in the sphere for now: its chunk's once handed over).
    if (flat_shading && kept > 0) {
      batch.room(kept);
      double* const in[6] = {batch.plane(0), batch.plane(1), batch.plane(2),
                             batch.plane(3), batch.plane(4), batch.plane(5)};
      for (size_t j = 0; j < kept; ++j) {
        // The centroid summed in view_spheres' order (triangle_step may have
        // swapped v1 and v2; the sum would then differ in its last bit), so
        // that flat_colors turns the face towards the eye on the same bits.
        const uint32_t at = tag[j];
        const auto& [a, b0, c0] =
            (at & kSureFace) ? unit.tri[at & ~kSureFace] : sc.cand_tri[at];
        const Vec3 p = (sc.world[a] + sc.world[flip ? c0 : b0] + sc.world[flip ? b0 : c0]) / 3.0;
        in[0][j] = p.x, in[1][j] = p.y, in[2][j] = p.z;
        if (at & kSureFace) {
          const uint32_t t = at & ~kSureFace;
          in[3][j] = sign * unit_face.nx[t], in[4][j] = sign * unit_face.ny[t],
          in[5][j] = sign * unit_face.nz[t];
        } else {
          const double* face = sc.amb_face.data() + 3 * size_t(at);
          in[3][j] = face[0], in[4][j] = face[1], in[5][j] = face[2];
        }
      }
      batch.added(kept, 0, surface);
    }
    if (kept > 0 && positions) {  // (triangle_step's samples test: done already)
      // (va, vb, vc hold valid vertex indices up to n rounded up to 16.)
      const size_t first = image->sink->add_positions(
          chunk, {sc.proj.data(), sc.depth.data(), sc.va.data(), sc.vb.data(), sc.vc.data()},
          kept, true);
      if (flat_shading) batch.offset_last(kept, first);
    }
    if (kept > 0 && shaded) {
      // Their face normals, of the side drawn (a kept face is a front face,
      // unless culling is not in world space: then sphere_faces says).
      for (auto& f : sc.kept_face) f.resize(kept);
      for (size_t j = 0; j < kept; ++j) {
        const uint32_t at = tag[j];
        Vec3 f;
        bool front = true;
        if (at & kSureFace) {
          const uint32_t t = at & ~kSureFace;
          f = {sign * unit_face.nx[t], sign * unit_face.ny[t], sign * unit_face.nz[t]};
        } else {
          const double* face = sc.amb_face.data() + 3 * size_t(at);
          f = {face[0], face[1], face[2]};
          front = (sc.amb_flags[at] & kFront) != 0;
        }
        if (!front) f = -f;
        sc.kept_face[0][j] = f.x, sc.kept_face[1][j] = f.y, sc.kept_face[2][j] = f.z;
      }
      ShadedTris sh;
      sh.normal = unit.unit.data();
      sh.negate = !(signed_radius > 0);
      for (int k = 0; k < 3; ++k) sh.face[k] = sc.kept_face[k].data();
      sh.material = scene.sphere_material[k];
      image->sink->add_shaded(
          chunk, {sc.proj.data(), sc.depth.data(), sc.va.data(), sc.vb.data(), sc.vc.data()},
          kept, sh);
    }
    return true;
  }
  for (uint32_t i = 0; i < nc; ++i) {
    if (sc.flags[i] & kNoFace) continue;
    const uint32_t t = sc.cand[i] & ~kSureFace;
    const auto& [a, b0, c0] = unit.tri[t];
    const uint32_t idx[3] = {a, flip ? c0 : b0, flip ? b0 : c0};
    const Vec3& w0 = sc.world[idx[0]];
    const Vec3& w1 = sc.world[idx[1]];
    const Vec3& w2 = sc.world[idx[2]];
    const Vec3 face{sc.face[3 * i], sc.face[3 * i + 1], sc.face[3 * i + 2]};
    const bool front = (sc.flags[i] & kFront) != 0;
    ++out.sphere_tris;
    // Emitter::triangle: world-space culling (spheres are one-sided) ...
    if (!front && s.cull == CullMode::kWorld) {
      ++out.culled;
      continue;
    }
    // ... then the snapped area: degenerate, projection-space culling, the
    // order (positive area: a front face's v[1] and v[2] swapped).
    const ProjectedVertex &p0 = sc.proj[idx[0]], &p1 = sc.proj[idx[1]], &p2 = sc.proj[idx[2]];
    const int64_t area =
        int64_t(p1.x - p0.x) * (p2.y - p0.y) - int64_t(p1.y - p0.y) * (p2.x - p0.x);
    if (area == 0) {
      ++out.degenerate;
      continue;
    }
    if (area > 0 && s.cull == CullMode::kProjection) {
      ++out.culled;
      continue;
    }
    if (image) {
      int32_t i0, i1, j0, j1;
      image->grid.pixels(std::min({p0.x, p1.x, p2.x}), std::max({p0.x, p1.x, p2.x}),
                         std::min({p0.y, p1.y, p2.y}), std::max({p0.y, p1.y, p2.y}), i0, i1, j0,
                         j1);
      if (i0 > i1 || j0 > j1) continue;  // no sample in its box
      if (occlusion && occlusion->hidden(i0, i1, j0, j1, std::min({p0.z, p1.z, p2.z}))) {
        ++out.hidden;
        continue;
      }
    }
    const uint32_t order[3] = {idx[0], area < 0 ? idx[2] : idx[1], area < 0 ? idx[1] : idx[2]};
    // Built in place (a ScreenTri is 300 bytes), or for the image in `local`
    // (every field it reads is written for each triangle).
    ScreenTri& st = image ? local : out.tris.emplace_back();
    for (int i = 0; i < 3; ++i) {
      const uint32_t vi = order[i];
      ScreenVertex& v = st.v[size_t(i)];
      v.x = sc.proj[vi].x;
      v.y = sc.proj[vi].y;
      v.z = sc.proj[vi].z;
      v.world = sc.world[vi];
      v.normal = normal(vi);
      if (gouraud) v.color = sc.color[vi];
    }
    st.prim = k;
    st.source_tri = t;
    st.face_normal = front ? face : -face;
    // The flat colour: view_spheres lights every face not culled in world space,
    // the same bits whenever it is done; for the image, in SIMD, later.
    if (image) {
      const VertexDepth d[3] = {sc.depth[order[0]], sc.depth[order[1]], sc.depth[order[2]]};
      const size_t at = image->sink->add(chunk, st, d);
      if (flat_shading) batch.add(at, (w0 + w1 + w2) / 3.0, face, surface);
    } else if (flat_shading) {
      st.flat_color = lit(scene, m, cam.eye, (w0 + w1 + w2) / 3.0, face);
    }
  }
  return true;
}

}  // namespace lockstep::opt::zsimd

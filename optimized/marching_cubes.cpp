// lockstep optimized: marching cubes with every cut edge computed once,
// shared by the triangles of the (up to four) cubes around it, in passes over
// slabs of the volume on TBB threads -- the pass structure of flying edges
// (Schroeder, Maynard, Geveci, "Flying edges: A high-performance scalable
// isocontouring algorithm", IEEE LDAV 2015), with the same case table, cut
// points (mc::cut_point, the tie rule that keeps cut points off samples equal
// to iso included) and triangle order as the reference (core/marching_cubes.h),
// so the surface is the reference's, vertex for vertex, once its soup is welded.
//
//   pass 1  per sample: below iso or not, and which of its three edges to the
//           next sample in +x, +y, +z is cut (one byte); per sample row
//           (fixed j, k): how many cuts of each axis it owns, and the first and
//           last sample with any
//   pass 2  per cube: its case, from the eight corners' below bits, only
//           between the first and last cut samples of its four sample rows
//           (trimming: a cut cube has a cut edge at its own sample), into a
//           row of scratch; per cube row: its triangles, the first and last
//           cube that is cut
//   offsets prefix sums over the rows: where each sample row's cut points and
//           each cube row's triangles go in the output
//   pass 3  per sample row: its cut points (x cuts, then y, then z, in order of
//           i); per cube row: its cases again (between its first and last
//           cut cube), its triangles, the index of each corner's cut
//           point found by counting cuts along the row from the row's offset
//           (one counter per row and axis the cube row uses)
// Passes 1 and 2 are plain loops over bytes written so that the compiler
// vectorises them (AVX2 at -march=x86-64-v3); every pass runs on slabs of z
// over the frame's threads (optimized/tiling.h).
#include "optimized/marching_cubes_simd.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <vector>

#include <hwy/highway.h>

#include "core/marching_cubes.h"
#include "optimized/tiling.h"

namespace lockstep::opt::simd {

namespace {

namespace hn = hwy::HWY_NAMESPACE;

// A byte array that is not zeroed on allocation (every byte is written by a
// pass); a large buffer (core/large_buffer.h).
using Bytes = std::vector<uint8_t, NoInitAllocator<uint8_t>>;
Bytes bytes(size_t n) { return Bytes(n); }

// Flag bits of a sample.
constexpr uint8_t kBelow = 1, kCutX = 2, kCutY = 4, kCutZ = 8;

struct SampleRow {
  uint32_t cuts[3] = {0, 0, 0};  // cut edges owned, per axis
  int first = 0, last = -1;      // samples with any cut (last < first: none)
  uint64_t offset = 0;           // its first cut point in the output
};

struct CubeRow {
  uint32_t triangles = 0;
  int first = 0, last = -1;  // cubes that are cut (last < first: none)
  uint64_t offset = 0;       // its first triangle in the output
};

// Pass 1 for one row of samples: f[i] = below | cut x << 1 | cut y << 2 | cut
// z << 3, where row r0 is compared with its next sample, ry and rz (the rows
// at j + 1 and k + 1, or r0 itself where there is none: no cut). Eight samples
// at a time (Highway, the build's static target): four compares, the bits
// combined in 32-bit lanes and narrowed to bytes.
void classify_row(const float* HWY_RESTRICT r0, const float* HWY_RESTRICT ry, const float* HWY_RESTRICT rz,
                  float iso, int nx, uint8_t* HWY_RESTRICT f) {
  const hn::ScalableTag<float> df;
  const hn::RebindToSigned<decltype(df)> di;
  const hn::Rebind<uint8_t, decltype(df)> d8;
  const int lanes = int(hn::Lanes(df));
  const auto viso = hn::Set(df, iso);
  const auto one = hn::Set(di, 1);
  auto bit = [&](const float* p) { return hn::And(hn::VecFromMask(di, hn::RebindMask(di, hn::Lt(hn::LoadU(df, p), viso))), one); };
  int i = 0;
  for (; i + lanes < nx; i += lanes) {
    const auto a = bit(r0 + i);
    const auto v = hn::Or(hn::Or(a, hn::ShiftLeft<1>(hn::Xor(a, bit(r0 + i + 1)))),
                          hn::Or(hn::ShiftLeft<2>(hn::Xor(a, bit(ry + i))), hn::ShiftLeft<3>(hn::Xor(a, bit(rz + i)))));
    hn::StoreU(hn::DemoteTo(d8, v), d8, f + i);
  }
  for (; i < nx; ++i) {
    const int a = r0[i] < iso;
    const int x = i + 1 < nx ? a ^ (r0[i + 1] < iso) : 0;
    f[i] = uint8_t(a | x << 1 | (a ^ (ry[i] < iso)) << 2 | (a ^ (rz[i] < iso)) << 3);
  }
}

// Pass 2 for one row of cubes: c[i] = the case of cube i, from the below bits
// of the four sample rows around it (j, k; j+1, k; j, k+1; j+1, k+1) at i and
// i + 1 (core/marching_cubes.h: corner v = (v&1 ^ v>>1&1, v>>1&1, v>>2&1)).
// 32 cubes at a time (Highway, bytes).
void case_row(const uint8_t* HWY_RESTRICT r00, const uint8_t* HWY_RESTRICT r10, const uint8_t* HWY_RESTRICT r01,
              const uint8_t* HWY_RESTRICT r11, int cubes, uint8_t* HWY_RESTRICT c) {
  const hn::ScalableTag<uint8_t> d;
  const int lanes = int(hn::Lanes(d));
  const auto one = hn::Set(d, 1);
  auto b = [&](const uint8_t* p) { return hn::And(hn::LoadU(d, p), one); };
  int i = 0;
  for (; i + lanes <= cubes; i += lanes) {
    const auto lo = hn::Or(hn::Or(b(r00 + i), hn::ShiftLeft<1>(b(r00 + i + 1))),
                           hn::Or(hn::ShiftLeft<2>(b(r10 + i + 1)), hn::ShiftLeft<3>(b(r10 + i))));
    const auto hi = hn::Or(hn::Or(hn::ShiftLeft<4>(b(r01 + i)), hn::ShiftLeft<5>(b(r01 + i + 1))),
                           hn::Or(hn::ShiftLeft<6>(b(r11 + i + 1)), hn::ShiftLeft<7>(b(r11 + i))));
    hn::StoreU(hn::Or(lo, hi), d, c + i);
  }
  for (; i < cubes; ++i)
    c[i] = uint8_t((r00[i] & 1) | (r00[i + 1] & 1) << 1 | (r10[i + 1] & 1) << 2 | (r10[i] & 1) << 3 |
                   (r01[i] & 1) << 4 | (r01[i + 1] & 1) << 5 | (r11[i + 1] & 1) << 6 | (r11[i] & 1) << 7);
}

// The first cube at or after i (before end) whose case is neither 0 nor 255
// (all corners on one side: no edge cut, no triangle), or end. Most cubes of a
// volume are such; eight at a time are skipped when every byte of a word has
// all its bits equal (the byte XOR itself rotated by one bit is 0).
inline int next_cut(const uint8_t* c, int i, int end) {
  for (; i + 8 <= end; i += 8) {
    uint64_t w;
    std::memcpy(&w, c + i, 8);
    const uint64_t rot = ((w << 1) & 0xFEFEFEFEFEFEFEFEull) | ((w >> 7) & 0x0101010101010101ull);
    if (const uint64_t x = w ^ rot) return i + (std::countr_zero(x) >> 3);
  }
  for (; i < end; ++i)
    if (uint8_t(c[i] + 1) > 1) return i;
  return end;
}

// The first sample at or after i (before end) with a cut edge (flag bits 1-3),
// or end; eight at a time.
inline int next_sample(const uint8_t* f, int i, int end) {
  for (; i + 8 <= end; i += 8) {
    uint64_t w;
    std::memcpy(&w, f + i, 8);
    if (const uint64_t x = w & 0x0E0E0E0E0E0E0E0Eull) return i + (std::countr_zero(x) >> 3);
  }
  for (; i < end; ++i)
    if (f[i] & 14) return i;
  return end;
}

// The axis-aligned runs of slabs of z: body(k0, k1) for samples or cubes k0 <= k < k1.
template <class Body>
void over_slabs(int n, int threads, const std::function<void(double)>& progress, Body body) {
  parallel_tiles(1, n, 1, std::max(1, std::min(8, n / (4 * resolve_threads(threads)) + 1)), threads, progress,
                 [&](int, int k0, int, int k1) { body(k0, k1); });
}

}  // namespace

Mesh marching_cubes(const Volume& v, const FrameOptions& options, FrameStats* stats) {
  const mc::Settings s = mc::settings(options.params, v.source);
  const std::array<mc::Case, 256>& table = mc::case_table();
  const int nx = v.nx, ny = v.ny, nz = v.nz;
  Mesh mesh;
  if (nx < 2 || ny < 2 || nz < 2) return mesh;
  // The reference compares each float sample, widened, with the double iso
  // value. The least float not below it classifies every float sample the
  // same way in float: x < iso_f exactly when double(x) < iso.
  float iso = float(s.iso);
  if (double(iso) < s.iso) iso = std::nextafter(iso, std::numeric_limits<float>::infinity());

  const size_t row_len = size_t(nx);
  const size_t samples = row_len * size_t(ny) * size_t(nz);
  Bytes flags = bytes(samples);
  std::vector<SampleRow, LargeAllocator<SampleRow>> srows(size_t(ny) * size_t(nz));

  // ---------------------------------------------------------------- pass 1
  over_slabs(nz, options.threads, nullptr, [&](int k0, int k1) {
    for (int k = k0; k < k1; ++k)
      for (int j = 0; j < ny; ++j) {
        const float* r0 = &v.data[v.index(0, j, k)];
        // No neighbour row: compare the row with itself (no cut).
        const float* ry = j + 1 < ny ? &v.data[v.index(0, j + 1, k)] : r0;
        const float* rz = k + 1 < nz ? &v.data[v.index(0, j, k + 1)] : r0;
        uint8_t* f = &flags[v.index(0, j, k)];
        classify_row(r0, ry, rz, iso, nx, f);
        SampleRow& r = srows[size_t(k) * size_t(ny) + size_t(j)];
        // Counted eight flag bytes at a time: one popcount per axis.
        uint32_t cx = 0, cy = 0, cz = 0;
        int i = 0;
        for (; i + 8 <= nx; i += 8) {
          uint64_t w;
          std::memcpy(&w, f + i, 8);
          cx += uint32_t(std::popcount(w & 0x0202020202020202ull));
          cy += uint32_t(std::popcount(w & 0x0404040404040404ull));
          cz += uint32_t(std::popcount(w & 0x0808080808080808ull));
        }
        for (; i < nx; ++i) {
          cx += (f[i] >> 1) & 1;
          cy += (f[i] >> 2) & 1;
          cz += (f[i] >> 3) & 1;
        }
        r.cuts[0] = cx;
        r.cuts[1] = cy;
        r.cuts[2] = cz;
        if (cx + cy + cz > 0) {
          int a = 0, b = nx - 1;
          while ((f[a] & 14) == 0) ++a;
          while ((f[b] & 14) == 0) --b;
          r.first = a;
          r.last = b;
        }
      }
  });

  // ---------------------------------------------------------------- pass 2
  const int cx_n = nx - 1, cy_n = ny - 1, cz_n = nz - 1;
  std::vector<CubeRow, LargeAllocator<CubeRow>> crows(size_t(cy_n) * size_t(cz_n));
  uint8_t ntri[256];
  for (int c = 0; c < 256; ++c) ntri[c] = table[size_t(c)].triangles;
  // A cube row's cases live in a row of scratch (pass 3 finds them again):
  // one byte per cube of the volume would be 16 MiB of fresh memory at 256^3,
  // written once and read once (issue #35: touch less).
  over_slabs(cz_n, options.threads, nullptr, [&](int k0, int k1) {
    Bytes cases = bytes(size_t(cx_n));
    for (int k = k0; k < k1; ++k)
      for (int j = 0; j < cy_n; ++j) {
        const uint8_t* r00 = &flags[v.index(0, j, k)];
        const uint8_t* r10 = &flags[v.index(0, j + 1, k)];
        const uint8_t* r01 = &flags[v.index(0, j, k + 1)];
        const uint8_t* r11 = &flags[v.index(0, j + 1, k + 1)];
        uint8_t* c = cases.data();
        CubeRow& row = crows[size_t(k) * size_t(cy_n) + size_t(j)];
        // Trimming (flying edges' "computational trimming"): a cut cube has a
        // cut edge at its own sample i in one of its four sample rows (if its
        // -x face is mixed, one of that face's four edges is cut; if that face
        // is uniform but the cube is not, one of its x edges is), so only cubes
        // between the rows' first and last cut samples can be cut, and a cube
        // row whose four sample rows have no cut has no case to find (most of
        // a CT scan's air and tissue). Cases outside the trimmed range are
        // never read (pass 3 reads row.first .. row.last).
        const SampleRow* sr[4] = {&srows[size_t(k) * size_t(ny) + size_t(j)],
                                  &srows[size_t(k) * size_t(ny) + size_t(j) + 1],
                                  &srows[(size_t(k) + 1) * size_t(ny) + size_t(j)],
                                  &srows[(size_t(k) + 1) * size_t(ny) + size_t(j) + 1]};
        int lo = cx_n, hi = -1;
        for (const SampleRow* q : sr)
          if (q->last >= q->first) {
            lo = std::min(lo, q->first);
            hi = std::max(hi, q->last);
          }
        hi = std::min(hi, cx_n - 1);
        row.last = -1;
        row.triangles = 0;
        if (hi < lo) continue;
        case_row(r00 + lo, r10 + lo, r01 + lo, r11 + lo, hi - lo + 1, c + lo);
        uint32_t n = 0;
        int last = -1;
        for (int i = next_cut(c, lo, hi + 1); i <= hi; i = next_cut(c, i + 1, hi + 1)) {
          if (last < 0) row.first = i;
          n += ntri[c[i]];
          last = i;
        }
        row.triangles = n;
        row.last = last;
      }
  });

  // ---------------------------------------------------------------- offsets
  uint64_t nv = 0, nt = 0;
  for (SampleRow& r : srows) {
    r.offset = nv;
    nv += uint64_t(r.cuts[0]) + r.cuts[1] + r.cuts[2];
  }
  for (CubeRow& r : crows) {
    r.offset = nt;
    nt += r.triangles;
  }
  mesh.vertices.resize(nv);
  mesh.triangles.resize(nt);

  // ---------------------------------------------------------------- pass 3
  // Which of a cube row's four sample rows an edge's first corner lies on
  // (0: j, k; 1: j+1, k; 2: j, k+1; 3: j+1, k+1), its step in x, and its axis.
  int edge_row[12], edge_dx[12], edge_axis[12];
  for (int e = 0; e < 12; ++e) {
    const int a = mc::kEdgeCorner[e][0];
    edge_row[e] = mc::corner_y(a) + 2 * mc::corner_z(a);
    edge_dx[e] = mc::corner_x(a);
    edge_axis[e] = mc::kEdgeAxis[e];
  }
  over_slabs(nz, options.threads, options.progress, [&](int k0, int k1) {
    Bytes cases = bytes(size_t(cx_n));
    // Cut points of the sample rows of slices k0 <= k < k1.
    for (int k = k0; k < k1; ++k)
      for (int j = 0; j < ny; ++j) {
        const SampleRow& r = srows[size_t(k) * size_t(ny) + size_t(j)];
        // The +z row two rows ahead, fetched now: the loop below reads its
        // rows at scattered samples, which the hardware prefetcher does not
        // follow (measured: the +z load was a quarter of this pass).
        if (k + 1 < nz && j + 2 < ny) {
          const float* ahead = &v.data[v.index(0, j + 2, k + 1)];
          for (int q = 0; q < nx; q += 16) __builtin_prefetch(ahead + q);
        }
        if (r.last < r.first) continue;
        Vec3f* ox_out = &mesh.vertices[r.offset];
        Vec3f* oy_out = ox_out + r.cuts[0];
        Vec3f* oz_out = oy_out + r.cuts[1];
        const uint8_t* f = &flags[v.index(0, j, k)];
        // The row, its neighbours in +y and +z, and the positions' fixed
        // coordinates, in locals: the stores below could alias v's fields.
        const float* row = &v.data[v.index(0, j, k)];
        const float* row_y = j + 1 < ny ? &v.data[v.index(0, j + 1, k)] : row;
        const float* row_z = k + 1 < nz ? &v.data[v.index(0, j, k + 1)] : row;
        const double ox = v.origin.x, sx = v.spacing.x, iso_d = s.iso;
        const double y = v.origin.y + j * v.spacing.y, z = v.origin.z + k * v.spacing.z;
        const double y1 = v.origin.y + (j + 1) * v.spacing.y, z1 = v.origin.z + (k + 1) * v.spacing.z;
        for (int i = r.first; i <= r.last; i = next_sample(f, i + 1, r.last + 1)) {
          const uint8_t m = f[i];
          // Volume::position's arithmetic, so the reference's bits.
          const Vec3 p{ox + i * sx, y, z};
          const double fa = row[i];
          if (m & kCutX) *ox_out++ = mc::cut_point(p, Vec3{ox + (i + 1) * sx, y, z}, fa, row[i + 1], iso_d);
          if (m & kCutY) *oy_out++ = mc::cut_point(p, Vec3{p.x, y1, z}, fa, row_y[i], iso_d);
          if (m & kCutZ) *oz_out++ = mc::cut_point(p, Vec3{p.x, y, z1}, fa, row_z[i], iso_d);
        }
      }
    // Triangles of the cube rows of slices k0 <= k < min(k1, nz - 1).
    for (int k = k0; k < std::min(k1, cz_n); ++k)
      for (int j = 0; j < cy_n; ++j) {
        const CubeRow& row = crows[size_t(k) * size_t(cy_n) + size_t(j)];
        if (row.last < row.first) continue;
        const SampleRow* sr[4] = {&srows[size_t(k) * size_t(ny) + size_t(j)],
                                  &srows[size_t(k) * size_t(ny) + size_t(j) + 1],
                                  &srows[(size_t(k) + 1) * size_t(ny) + size_t(j)],
                                  &srows[(size_t(k) + 1) * size_t(ny) + size_t(j) + 1]};
        const uint8_t* f[4] = {&flags[v.index(0, j, k)], &flags[v.index(0, j + 1, k)], &flags[v.index(0, j, k + 1)],
                               &flags[v.index(0, j + 1, k + 1)]};
        // Before the row's first cut cube, no sample row owns a cut edge of the
        // axes this cube row reads (such an edge would cut a cube before it):
        // each counter starts at its run's beginning.
        uint64_t next[4][3];
        for (int q = 0; q < 4; ++q) {
          next[q][0] = sr[q]->offset;
          next[q][1] = sr[q]->offset + sr[q]->cuts[0];
          next[q][2] = sr[q]->offset + sr[q]->cuts[0] + sr[q]->cuts[1];
        }
        // The row's cases again, between its first and last cut cube (pass 2's).
        uint8_t* c = cases.data();
        case_row(f[0] + row.first, f[1] + row.first, f[2] + row.first, f[3] + row.first, row.last - row.first + 1,
                 c + row.first);
        std::array<uint32_t, 3>* tri = &mesh.triangles[row.offset];
        // Cubes with no cut edge are skipped: none of the counters this row
        // reads would move there (each counts edges of the cube at its sample).
        for (int i = row.first; i <= row.last; i = next_cut(c, i + 1, row.last + 1)) {
          const mc::Case& cube = table[c[i]];
          for (int t = 0; t < cube.triangles; ++t) {
            std::array<uint32_t, 3> out;
            for (int q = 0; q < 3; ++q) {
              const int e = cube.tri[size_t(t)][size_t(q)];
              const int r = edge_row[e], axis = edge_axis[e];
              // The cut point of the edge at sample i + dx: the counter at i,
              // past sample i's own cut of that axis when dx = 1.
              out[size_t(q)] = uint32_t(next[r][axis] + (edge_dx[e] ? (f[r][i] >> (1 + axis)) & 1 : 0));
            }
            *tri++ = out;
          }
          for (int q = 0; q < 4; ++q) {
            const uint8_t m = f[q][i];
            next[q][0] += (m >> 1) & 1;
            next[q][1] += (m >> 2) & 1;
            next[q][2] += (m >> 3) & 1;
          }
        }
      }
  });
  if (stats) {
    stats->items = v.cells();
    if (mesh.triangles.empty())
      if (std::string note = mc::empty_note(v.data, s.iso); !note.empty()) stats->notes.push_back(std::move(note));
  }
  return mesh;
}

}  // namespace lockstep::opt::simd

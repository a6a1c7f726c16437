// lockstep tests: mesh files (io/mesh_io.h) and welding and topology
// (core/mesh.h): what is written reads back exactly, in every format; bad files
// are one InputError naming the file; topology counts what it says.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "core/error.h"
#include "core/mesh.h"
#include "io/mesh_io.h"

namespace lockstep {
namespace {

namespace fs = std::filesystem;

// A tetrahedron, outward counter-clockwise, with coordinates no short decimal holds.
Mesh tetrahedron() {
  Mesh m;
  m.vertices = {{0.1f, 0.2f, 0.3f}, {1.0f / 3, 0, 0}, {0, 1e-7f, 1}, {0, 1.7e7f, -0.0f}};
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return m;
}

fs::path tmp(const std::string& name) { return fs::temp_directory_path() / ("lockstep-mesh-io-" + name); }

void expect_same(const Mesh& a, const Mesh& b) {
  ASSERT_EQ(a.vertices.size(), b.vertices.size());
  ASSERT_EQ(a.triangles.size(), b.triangles.size());
  for (size_t i = 0; i < a.vertices.size(); ++i) {
    EXPECT_EQ(a.vertices[i].x, b.vertices[i].x) << "vertex " << i;
    EXPECT_EQ(a.vertices[i].y, b.vertices[i].y) << "vertex " << i;
    EXPECT_EQ(a.vertices[i].z, b.vertices[i].z) << "vertex " << i;
  }
  for (size_t i = 0; i < a.triangles.size(); ++i) EXPECT_EQ(a.triangles[i], b.triangles[i]) << "triangle " << i;
}

TEST(MeshIo, RoundTripsEveryFormat) {
  const Mesh m = tetrahedron();
  for (const auto& [name, ascii] : {std::pair{"bin.ply", false}, {"ascii.ply", true}, {"t.obj", false}, {"t.off", false}}) {
    const fs::path p = tmp(name);
    write_mesh(m, p.string(), ascii);
    expect_same(m, read_mesh(p.string()));
    fs::remove(p);
  }
}

std::string bytes_of(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Binary PLY is written directly (io/mesh_io.h): CGAL's writer's bytes, exactly.
TEST(MeshIo, DirectBinaryPlyIsCgals) {
  Mesh big;  // more than the writer's 1 MiB buffer of faces (13 bytes each)
  for (uint32_t i = 0; i < 100000; ++i) {
    big.vertices.push_back({float(i) * 0.37f, -float(i) / 3, 1e-3f * float(i % 97)});
    big.triangles.push_back({i, (i * 7 + 1) % 100000, (i * 13 + 2) % 100000});
  }
  Mesh signs;  // -0 and +0, a denormal, the largest float
  signs.vertices = {{0.0f, -0.0f, 1e-40f}, {3.4028235e38f, -1.0f, 0.5f}, {1, 2, 3}};
  signs.triangles = {{0, 1, 2}};
  int n = 0;
  for (const Mesh& m : {tetrahedron(), Mesh{}, big, signs}) {
    const fs::path direct = tmp("direct.ply"), cgal = tmp("cgal.ply");
    write_mesh(m, direct.string());
    write_mesh_through_cgal(m, cgal.string());
    const std::string a = bytes_of(direct), b = bytes_of(cgal);
    ASSERT_EQ(a.size(), b.size()) << "mesh " << n << ": " << m.vertices.size() << " vertices, " << m.triangles.size()
                                  << " triangles";
    size_t at = 0;
    while (at < a.size() && a[at] == b[at]) ++at;
    EXPECT_EQ(at, a.size()) << "mesh " << n << ": first differing byte " << at << " of " << a.size();
    fs::remove(direct);
    fs::remove(cgal);
    ++n;
  }
}

TEST(MeshIo, AsciiPlyIsText) {
  const fs::path p = tmp("text.ply");
  write_mesh(tetrahedron(), p.string(), true);
  std::ifstream in(p);
  std::string first, format;
  std::getline(in, first);
  std::getline(in, format);
  EXPECT_EQ(first, "ply");
  EXPECT_EQ(format, "format ascii 1.0");
  fs::remove(p);
}

TEST(MeshIo, BadFilesAreInputErrors) {
  EXPECT_THROW(read_mesh(tmp("missing.ply").string()), InputError);
  const fs::path junk = tmp("junk.ply");
  std::ofstream(junk) << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n1\n";
  EXPECT_THROW(read_mesh(junk.string()), InputError);
  const fs::path quad = tmp("quad.obj");
  std::ofstream(quad) << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
  try {
    read_mesh(quad.string());
    ADD_FAILURE() << "a quad was read as a triangle mesh";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("quad.obj"), std::string::npos) << e.what();
  }
  EXPECT_THROW(check_mesh_path((tmp("x") / "no-folder" / "m.ply").string()), InputError);
  EXPECT_THROW(check_mesh_path(tmp("m.png").string()), InputError);
  fs::remove(junk);
  fs::remove(quad);
}

// Coloured polygons (the radiosity patches' PLY): the header a viewer reads,
// then every number back from the binary body, colours clamped and rounded.
TEST(MeshIo, ColouredPolygonsReadBack) {
  ColouredPolygons p;
  p.value_name = "radiosity";
  p.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0.5f, -1}};
  p.vertex_values = {{0, 0.5f, 1}, {2, -1, 0.25f}, {0.1f, 0.2f, 0.3f}, {1, 1, 1}, {0.998f, 0.999f, 1e-3f}};
  p.faces = {{0, 1, 2, 3}, {1, 4, 2, 0}};
  p.corners = {4, 3};
  p.face_values = {{0.5f, 7, 0}, {0.25f, 0.125f, 1.5f}};
  p.face_groups = {3, -1};
  const fs::path file = tmp("coloured.ply");
  write_coloured_polygons(p, file.string());
  std::ifstream in(file, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const size_t body = bytes.find("end_header\n") + 11;
  ASSERT_NE(body, std::string::npos + 11);
  const std::string header = bytes.substr(0, body);
  EXPECT_NE(header.find("element vertex 5\n"), std::string::npos) << header;
  EXPECT_NE(header.find("element face 2\n"), std::string::npos) << header;
  EXPECT_NE(header.find("property float radiosity_g\n"), std::string::npos) << header;
  size_t at = body;
  auto take = [&](auto v) {
    std::memcpy(&v, bytes.data() + at, sizeof v);
    at += sizeof v;
    return v;
  };
  auto byte = [](float v) { return uint8_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255)); };
  auto expect_values = [&](const Vec3f& want, const std::string& what) {
    EXPECT_EQ(take(uint8_t()), byte(want.x)) << what;
    EXPECT_EQ(take(uint8_t()), byte(want.y)) << what;
    EXPECT_EQ(take(uint8_t()), byte(want.z)) << what;
    EXPECT_EQ(take(float()), want.x) << what;
    EXPECT_EQ(take(float()), want.y) << what;
    EXPECT_EQ(take(float()), want.z) << what;
  };
  for (size_t v = 0; v < p.vertices.size(); ++v) {
    EXPECT_EQ(take(float()), p.vertices[v].x);
    EXPECT_EQ(take(float()), p.vertices[v].y);
    EXPECT_EQ(take(float()), p.vertices[v].z);
    expect_values(p.vertex_values[v], "vertex " + std::to_string(v));
  }
  for (size_t k = 0; k < p.faces.size(); ++k) {
    ASSERT_EQ(take(uint8_t()), p.corners[k]);
    for (int c = 0; c < p.corners[k]; ++c) EXPECT_EQ(take(int32_t()), int32_t(p.faces[k][size_t(c)]));
    expect_values(p.face_values[k], "face " + std::to_string(k));
    EXPECT_EQ(take(int32_t()), p.face_groups[k]);
  }
  EXPECT_EQ(at, bytes.size());
  // Only PLY keeps colours; nothing is written for another extension.
  EXPECT_THROW(write_coloured_polygons(p, tmp("coloured.obj").string()), InputError);
  EXPECT_FALSE(fs::exists(tmp("coloured.obj")));
  fs::remove(file);
}

TEST(MeshTopology, ClosedTetrahedronAndWhatBreaksIt) {
  const Topology t = topology(tetrahedron());
  EXPECT_TRUE(t.closed_manifold()) << t.str();
  EXPECT_EQ(t.euler(), 2);
  EXPECT_EQ(t.components, 1);
  Mesh open = tetrahedron();
  open.triangles.pop_back();
  EXPECT_EQ(topology(open).boundary_edges, 3);
  Mesh flipped = tetrahedron();
  std::swap(flipped.triangles[0][1], flipped.triangles[0][2]);
  EXPECT_EQ(topology(flipped).misoriented_edges, 3);
  Mesh twice = tetrahedron();
  twice.triangles.push_back(twice.triangles[0]);
  EXPECT_GT(topology(twice).nonmanifold_edges, 0);
  // Two tetrahedra sharing one vertex: edges fine, the vertex pinched.
  Mesh pinched = tetrahedron();
  for (const Vec3f& v : tetrahedron().vertices) pinched.vertices.push_back(Vec3f(2 * v.x - 5, 2 * v.y - 5, 2 * v.z - 5));
  pinched.vertices[4] = pinched.vertices[0];
  for (auto t2 : tetrahedron().triangles) pinched.triangles.push_back({t2[0] + 4, t2[1] + 4, t2[2] + 4});
  const Topology p = topology(weld(pinched));
  EXPECT_EQ(p.nonmanifold_vertices, 1) << p.str();
  EXPECT_EQ(p.boundary_edges + p.nonmanifold_edges + p.misoriented_edges, 0) << p.str();
}

TEST(MeshWeld, SoupBecomesIndexed) {
  const Mesh t = tetrahedron();
  Mesh soup;
  for (const auto& tri : t.triangles) {
    const uint32_t base = uint32_t(soup.vertices.size());
    for (uint32_t v : tri) soup.vertices.push_back(t.vertices[v]);
    soup.triangles.push_back({base, base + 1, base + 2});
  }
  const Mesh w = weld(soup);
  EXPECT_EQ(w.vertices.size(), 4u);
  EXPECT_EQ(w.triangles.size(), 4u);
  EXPECT_TRUE(topology(w).closed_manifold());
  // -0 and +0 are one position.
  Mesh signs;
  signs.vertices = {{0.0f, 0, 0}, {-0.0f, 0, 0}};
  EXPECT_EQ(weld(signs).vertices.size(), 1u);
}

}  // namespace
}  // namespace lockstep

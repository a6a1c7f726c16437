// lockstep io: mesh files through CGAL's polygon-soup I/O (see io/mesh_io.h).
#include "io/mesh_io.h"

#include <CGAL/IO/polygon_soup_io.h>
#include <CGAL/Simple_cartesian.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <vector>

#include "core/error.h"
#include "core/quiet_stderr.h"

namespace lockstep {

namespace {

// Float points: the files store what the mesh holds (PLY "property float").
using Point = CGAL::Simple_cartesian<float>::Point_3;
namespace fs = std::filesystem;

std::string extension(const std::string& path) {
  std::string e = fs::path(path).extension().string();
  for (char& c : e) c = char(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

}  // namespace

void check_mesh_path(const std::string& path) {
  const fs::path p(path);
  const fs::path dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw InputError(path, 0, "cannot write mesh: folder " + dir.string() + " does not exist");
  if (fs::is_directory(p, ec)) throw InputError(path, 0, "cannot write mesh: is a folder");
  const std::string e = extension(path);
  if (e != ".ply" && e != ".obj" && e != ".off")
    throw InputError(path, 0, "cannot write mesh: unknown format '" + e + "' (.ply, .obj or .off)");
}

void write_mesh(const Mesh& mesh, const std::string& path, bool ascii) {
  check_mesh_path(path);
  std::vector<Point> points;
  points.reserve(mesh.vertices.size());
  for (const Vec3f& v : mesh.vertices) points.emplace_back(v.x, v.y, v.z);
  std::vector<std::array<std::size_t, 3>> polygons;
  polygons.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles) polygons.push_back({t[0], t[1], t[2]});
  // The temporary keeps the extension: CGAL picks the format by it.
  const fs::path p(path);
  const std::string tmp = (p.parent_path() / (".tmp-" + p.filename().string())).string();
  // 9 significant digits round-trip a float in text formats.
  const bool ok = CGAL::IO::write_polygon_soup(
      tmp, points, polygons, CGAL::parameters::use_binary_mode(!ascii).stream_precision(9));
  std::error_code ec;
  if (!ok) {
    fs::remove(tmp, ec);
    throw InputError(path, 0, "cannot write mesh");
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw InputError(path, 0, "cannot write mesh: " + ec.message());
  }
}

Mesh read_mesh(const std::string& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) throw InputError(path, 0, fs::exists(path, ec) ? "not a file" : "no such file");
  std::vector<Point> points;
  std::vector<std::vector<std::size_t>> polygons;
  bool ok = false;
  {
    QuietStderr quiet;  // CGAL's readers print their complaints; the message below says it
    ok = CGAL::IO::read_polygon_soup(path, points, polygons);
  }
  if (!ok) throw InputError(path, 0, "cannot read mesh (not a valid .ply, .obj or .off file)");
  Mesh m;
  m.vertices.reserve(points.size());
  for (const Point& q : points) {
    if (!std::isfinite(q.x()) || !std::isfinite(q.y()) || !std::isfinite(q.z()))
      throw InputError(path, 0, "vertex " + std::to_string(m.vertices.size()) + " is not finite");
    m.vertices.emplace_back(q.x(), q.y(), q.z());
  }
  m.triangles.reserve(polygons.size());
  for (const auto& poly : polygons) {
    if (poly.size() != 3)
      throw InputError(path, 0, "face " + std::to_string(m.triangles.size()) + " has " + std::to_string(poly.size()) +
                                    " vertices (only triangles are read)");
    for (std::size_t i : poly)
      if (i >= points.size())
        throw InputError(path, 0, "face " + std::to_string(m.triangles.size()) + " names vertex " + std::to_string(i) +
                                      " of " + std::to_string(points.size()));
    m.triangles.push_back({uint32_t(poly[0]), uint32_t(poly[1]), uint32_t(poly[2])});
  }
  return m;
}

}  // namespace lockstep

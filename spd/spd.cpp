// lockstep spd: the scene table and generate() (see spd/spd.h).
#include "spd/spd.h"

#include <array>
#include <charconv>

#include "spd/scenes.h"

namespace lockstep::spd {

namespace {

struct Entry {
  SceneSpec spec;
  void (*make)(Writer&, int);
};

// Maximum sizes keep a file under about 200 MB, about a million entities
// (balls grows 9x a step, jacks 8x, sombrero and tetra 4x; tessellation turns
// a sphere into 6*2*U*V patches, U = V = 3 but 2 for jacks), and inside the
// SPD's own limits (mount's hash shifts by 7 - size bits).
constexpr std::array<Entry, 12> kScenes = {{
    {{"balls", 4, 6, 4, true, "sphereflake: sum of 9^k spheres, k = 0 .. size, on a floor square"},
     balls},
    {{"cornell", 1, 1, 1, false,
      "the Cornell box (not an SPD program): 16 quads in mm, the light an emitter"},
     cornell},
    {{"gears", 4, 12, 12, false, "size^3 gears: concave 144-gons and 144 rectangles each"}, gears},
    {{"jacks", 1, 6, 4, true, "recursive jacks: cylinders and spheres, 8x per level"}, jacks},
    {{"lattice", 12, 40, 16, true, "(size+1)^3 spheres joined by cylinders"}, lattice},
    {{"mount", 6, 7, 7, true, "fractal mountain: 2*4^size triangles and 4 glass spheres"}, mount},
    {{"rings", 7, 20, 8, true,
      "pyramid of dodecahedral rings: 30 cylinders and spheres per object"},
     rings},
    {{"shells", 5, 12, 5, true, "spiral shell: 180*2^size+1 overlapping spheres"}, shells},
    {{"sombrero", 1, 5, 5, false, "height field: 2*(32*2^(size-1)-1)^2 triangles"}, sombrero},
    {{"teapot", 6, 64, 64, false,
      "Newell teapot: 64*size^2 triangle patches less degenerates, checkerboard"},
     teapot},
    {{"tetra", 6, 9, 9, false, "Sierpinski tetrahedron: 4^size triangles"}, tetra},
    {{"tree", 11, 16, 12, true, "branching tree: 2^(size+1)-1 cones and spheres"}, tree},
}};

constexpr std::array<SceneSpec, kScenes.size()> specs() {
  std::array<SceneSpec, kScenes.size()> s{};
  for (size_t i = 0; i < kScenes.size(); ++i) s[i] = kScenes[i].spec;
  return s;
}
constexpr std::array<SceneSpec, kScenes.size()> kSpecs = specs();

}  // namespace

std::span<const SceneSpec> scenes() { return kSpecs; }

const SceneSpec* find(std::string_view name) {
  for (const SceneSpec& s : kSpecs)
    if (s.name == name) return &s;
  return nullptr;
}

std::string names() {
  std::string out;
  for (const SceneSpec& s : kSpecs) out += (out.empty() ? "" : ", ") + std::string(s.name);
  return out;
}

std::string generate(std::string_view name, int size, bool tess) {
  for (const Entry& e : kScenes) {
    if (e.spec.name != name) continue;
    const int max = tess ? e.spec.max_size_tess : e.spec.max_size;
    if (size < 1 || size > max)
      throw SpdError("spd " + std::string(name) + (tess ? " --tess" : "") +
                     ": size must be in 1 .. " + std::to_string(max) + ", got " +
                     std::to_string(size));
    Writer w(tess);
    e.make(w, size);
    return w.take();
  }
  throw SpdError("unknown SPD scene '" + std::string(name) + "' (known: " + names() + ")");
}

std::optional<Request> parse_stem(std::string_view stem) {
  Request r;
  if (stem.ends_with("-tess")) {
    r.tess = true;
    stem.remove_suffix(5);
  }
  const size_t dash = stem.rfind('-');
  if (dash == std::string_view::npos || dash == 0) return std::nullopt;
  const std::string_view num = stem.substr(dash + 1);
  const auto res = std::from_chars(num.data(), num.data() + num.size(), r.size);
  if (res.ec != std::errc() || res.ptr != num.data() + num.size() || num.empty())
    return std::nullopt;
  r.name = std::string(stem.substr(0, dash));
  const SceneSpec* s = find(r.name);
  if (s == nullptr || r.size < 1 || r.size > (r.tess ? s->max_size_tess : s->max_size))
    return std::nullopt;
  return r;
}

}  // namespace lockstep::spd

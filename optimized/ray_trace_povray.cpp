// lockstep optimized: the ray-tracing family's peer row, POV-Ray 3.7, run as
// a process (see optimized/ray_trace_povray.h).
//
// The scene, written from lockstep's Scene (not from the NFF file):
//   spheres    sphere { c, |r| }: POV-Ray's spheres are solids, as the
//              tracer's are (core/ray_trace.h); a negative radius (NFF: only
//              the inside is seen) is not drawn differently;
//   polygons   one mesh { } of the polygons' triangulation (Scene::tri_vertex,
//              the triangles every row draws): triangle { } for 'p',
//              smooth_triangle { } with the vertex normals for 'pp' patches;
//   cones      cone { base, r0, apex, r1 open } (cylinder { } when r0 = r1):
//              NFF's cones are open;
//   lights     light_source { position, colour }: the light's colour, or NFF's
//              default 1/sqrt(lights) (core/shading.h) written out; with
//              shadows=none every object is no_shadow (a shadowless light
//              would lose its highlights too). lockstep's attenuation and
//              spotlights are refused (InputError): POV-Ray's fade and
//              spotlight models are other functions;
//   materials  one texture per material: pigment rgbt <C, T> (transmit: not
//              filtered by the colour, Whitted's kt), finish { ambient
//              0.1 kd / (1 - T) (kAmbient) diffuse kd / (1 - T) phong ks
//              phong_size shine reflection ks }, interior { ior } when T > 0
//              (POV-Ray scales a surface's ambient and diffuse by its opacity
//              1 - T, the tracer does not: undone; measured exact at depth 1
//              on a T = 0.5 ball); depth is max_trace_level, cutoff
//              adc_bailout.
//   output     linear: assumed_gamma 1 and File_Gamma=1, 16-bit PPM (+FP16),
//              no antialiasing (-A), no display (-D). POV-Ray clips each
//              channel to [0, 1]; the reference does not clamp, so the lights,
//              ambient_light and background are written at 1/S and the image
//              read back times S (exposure_scale: a power-of-2 bound on any
//              pixel's value, at most 16; 16-bit steps of S/65535).
//
// The camera: POV-Ray's perspective camera sends the ray through image
// position (x + 1/2, y + 1/2) of pixel (x, y) (measured: a plane at distance 1
// whose pigment is its x or y coordinate, 8x8 pixels, gives -0.35 .. 0.35 in
// steps of 0.1 for right = up = 0.8) in the direction
//   direction + ((x + 1/2)/W - 1/2) right + (1/2 - (y + 1/2)/H) up
// (row 0 at the top), with the vectors used as given when there is no
// look_at. The row writes location = from, direction = forward,
// right = W s right_c, up = H s up_c (Camera::from_view's unit vectors and
// pitch s), so that this is forward + sx(x) right_c + sy(y) up_c: exactly
// Camera::primary's direction before it is normalised. Nothing is mirrored:
// POV-Ray's "left-handed" coordinates are only its default camera's
// right = +x, up = +y, direction = +z; the world is written as it is.
// POV-Ray has no near plane: the view's hither is not applied.
//
// What POV-Ray's model defines differently (the shading difference is
// measured against the reference in registry/ray_trace_row.cpp, the visibility and
// shadows agreement in tests/povray_test.cpp):
//   - NFF's one-sidedness: POV-Ray draws both sides of every surface, so a
//     polygon seen from behind (one-sided in NFF unless it transmits) hides
//     what lies behind it; shadow rays are blocked by both sides in both;
//   - transparent surfaces: POV-Ray lets light through them to the points
//     behind (shadows filtered by the transmit value); the tracer's shadow
//     rays are blocked by them;
//   - smooth triangles: POV-Ray interpolates the vertex normals its own way,
//     not with the reference's barycentric weights in the same triangle;
//   - its limits: hits beyond 1e7 from a ray's origin are dropped (counted in
//     FrameStats::dropped), bounding boxes are kept in single precision (wrong
//     far from the origin), and blockers nearer than 1e-3 to a shadow ray's
//     origin are ignored (its SHADOW_TOLERANCE).
#include "optimized/ray_trace_povray.h"

#include <algorithm>
#include <cerrno>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include "core/camera.h"
#include "core/error.h"
#include "core/ray_trace.h"
#include "core/shading.h"
#include "core/timer.h"

#ifndef LOCKSTEP_POVRAY_PATH
#define LOCKSTEP_POVRAY_PATH ""
#endif
#ifndef LOCKSTEP_POVRAY_VERSION
#define LOCKSTEP_POVRAY_VERSION ""
#endif

namespace lockstep::opt::povray {

std::string program() { return LOCKSTEP_POVRAY_PATH; }
std::string version() { return LOCKSTEP_POVRAY_VERSION; }

bool available() {
#ifdef LOCKSTEP_HAVE_POVRAY
  static const bool ok = !program().empty() && ::access(program().c_str(), X_OK) == 0;
  return ok;
#else
  return false;
#endif
}

namespace {

// POV-Ray's MAX_DISTANCE: an intersection farther than this along a ray is none.
constexpr double kMaxDistance = 1e7;

std::string num(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}
std::string vec(const Vec3& v) { return "<" + num(v.x) + "," + num(v.y) + "," + num(v.z) + ">"; }

void check_lights(const Scene& scene) {
  for (size_t k = 0; k < scene.lights.size(); ++k) {
    const Light& l = scene.lights[k];
    if (l.spot || l.atten.x != 1 || l.atten.y != 0 || l.atten.z != 0)
      throw InputError(scene.source, 0,
                       "light " + std::to_string(k + 1) +
                           " has lockstep's attenuation or spotlight extension: the povray row cannot draw "
                           "it the same way (POV-Ray's fade and spotlight are other functions)");
  }
}

// Distance from p to the box [lo, hi] (0 inside) and to its farthest corner.
void box_distances(const Vec3& p, const Vec3& lo, const Vec3& hi, double& nearest, double& farthest) {
  double n2 = 0, f2 = 0;
  for (int a = 0; a < 3; ++a) {
    const double c = a == 0 ? p.x : a == 1 ? p.y : p.z;
    const double l = a == 0 ? lo.x : a == 1 ? lo.y : lo.z;
    const double h = a == 0 ? hi.x : a == 1 ? hi.y : hi.z;
    const double d = c < l ? l - c : c > h ? c - h : 0;
    const double f = std::max(std::abs(c - l), std::abs(c - h));
    n2 += d * d;
    f2 += f * f;
  }
  nearest = std::sqrt(n2);
  farthest = std::sqrt(f2);
}

// What POV-Ray's absolute limits leave out, per primitive (its bounding box):
//   beyond    reaching farther than MAX_DISTANCE from the eye;
//   tiny      every primitive when the scene (primitives, eye and lights) is
//             smaller than kTinyScene: POV-Ray's tolerances are absolute
//             (hits nearer than 1e-6 along a ray are none, shadow blockers
//             nearer than 1e-3 to the ray's origin are ignored), not relative
//             to the scene;
//   far       primitives whose coordinates exceed kFarRatio times the scene's
//             size: POV-Ray keeps bounding boxes in single precision, so
//             their rounding (2^-24 of the coordinates) reaches 1e-5 of the
//             scene and rays near a box's edge may miss what they should hit.
constexpr double kTinyScene = 0.1;
constexpr double kFarRatio = 1e-5 * 0x1p24;  // about 168
struct Reach {
  uint64_t beyond = 0, tiny = 0, far = 0;
  double magnitude = 0, size = 0;
};
Reach reach(const Scene& s) {
  struct Box {
    Vec3 lo, hi;
  };
  std::vector<Box> boxes;
  for (uint32_t i = 0; i < s.sphere_count(); ++i) {
    const double a = std::abs(s.sphere_radius[i]);
    boxes.push_back({s.sphere_center[i] - Vec3{a, a, a}, s.sphere_center[i] + Vec3{a, a, a}});
  }
  for (uint32_t p = 0; p < s.polygon_count(); ++p) {
    Vec3 lo{kInfinity, kInfinity, kInfinity}, hi = -lo;
    for (const Vec3& v : s.polygon_vertices(p)) {
      lo = {std::min(lo.x, v.x), std::min(lo.y, v.y), std::min(lo.z, v.z)};
      hi = {std::max(hi.x, v.x), std::max(hi.y, v.y), std::max(hi.z, v.z)};
    }
    if (lo.x <= hi.x) boxes.push_back({lo, hi});
  }
  for (uint32_t c = 0; c < s.cone_count(); ++c) {
    const double a = std::max(s.cone_r0[c], s.cone_r1[c]);
    const Vec3& b = s.cone_base[c];
    const Vec3& e = s.cone_apex[c];
    boxes.push_back({Vec3{std::min(b.x, e.x), std::min(b.y, e.y), std::min(b.z, e.z)} - Vec3{a, a, a},
                     Vec3{std::max(b.x, e.x), std::max(b.y, e.y), std::max(b.z, e.z)} + Vec3{a, a, a}});
  }
  Reach r;
  Vec3 lo = s.view.from, hi = s.view.from;
  auto grow = [&](const Vec3& p) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  };
  for (const Light& l : s.lights) grow(l.position);
  for (const Box& b : boxes) {
    grow(b.lo);
    grow(b.hi);
  }
  r.size = length(hi - lo);
  std::vector<double> magnitude(boxes.size());
  for (size_t i = 0; i < boxes.size(); ++i) {
    const Box& b = boxes[i];
    double n, f;
    box_distances(s.view.from, b.lo, b.hi, n, f);
    if (f > kMaxDistance) ++r.beyond;
    magnitude[i] = std::max({std::abs(b.lo.x), std::abs(b.lo.y), std::abs(b.lo.z), std::abs(b.hi.x),
                             std::abs(b.hi.y), std::abs(b.hi.z)});
    r.magnitude = std::max(r.magnitude, magnitude[i]);
  }
  if (!(r.size >= kTinyScene)) {
    r.tiny = boxes.size();
    return r;
  }
  for (size_t i = 0; i < boxes.size(); ++i) r.far += magnitude[i] > kFarRatio * r.size;
  return r;
}

// Reads a binary PPM (P6; POV-Ray writes comment lines after the magic
// number) of width x height pixels, 8 or 16 bits, into an image.
Image read_ppm(const std::string& path, int width, int height, double gain) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw std::runtime_error("povray wrote no image (" + path + ")");
  std::string data((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  size_t i = 0;
  auto token = [&]() -> long {
    for (;;) {
      while (i < data.size() && std::isspace(static_cast<unsigned char>(data[i]))) ++i;
      if (i < data.size() && data[i] == '#') {
        while (i < data.size() && data[i] != '\n') ++i;
        continue;
      }
      break;
    }
    const size_t s = i;
    while (i < data.size() && !std::isspace(static_cast<unsigned char>(data[i]))) ++i;
    return s == i ? -1 : std::strtol(data.c_str() + s, nullptr, 10);
  };
  if (data.size() < 2 || data[0] != 'P' || data[1] != '6') throw std::runtime_error("povray's image is not a P6 PPM");
  i = 2;
  const long w = token(), h = token(), maxval = token();
  ++i;  // the one blank after maxval
  if (w != width || h != height || maxval <= 0 || maxval > 65535)
    throw std::runtime_error("povray's image is " + std::to_string(w) + "x" + std::to_string(h) + ", not " +
                             std::to_string(width) + "x" + std::to_string(height));
  const int bytes = maxval > 255 ? 2 : 1;
  if (data.size() < i + size_t(w) * size_t(h) * 3 * bytes) throw std::runtime_error("povray's image is truncated");
  Image img = Image::uninitialized(width, height);
  const auto* p = reinterpret_cast<const unsigned char*>(data.data() + i);
  const double scale = gain / double(maxval);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      float* q = img.pixel(x, y);
      for (int c = 0; c < 3; ++c) {
        const unsigned v = bytes == 2 ? (unsigned(p[0]) << 8) | p[1] : p[0];
        p += bytes;
        q[c] = float(double(v) * scale);
      }
      q[3] = 1.0f;
    }
  return img;
}

// "(0.123 seconds)" on the line that starts with label, or -1.
double seconds_of(const std::string& log, const std::string& label) {
  const std::regex re(label + R"(:[^(\n]*\(([0-9.]+) seconds\))");
  std::smatch m;
  if (std::regex_search(log, m, re)) return std::atof(m[1].str().c_str());
  return -1;
}
uint64_t count_of(const std::string& log, const std::string& label) {
  const std::regex re(label + R"(:\s+([0-9]+))");
  std::smatch m;
  if (std::regex_search(log, m, re)) return std::strtoull(m[1].str().c_str(), nullptr, 10);
  return 0;
}

std::string tail(const std::string& s, size_t n) { return s.size() <= n ? s : "..." + s.substr(s.size() - n); }

// A temporary folder, removed with everything in it when this goes.
struct TempDir {
  std::filesystem::path path;
  TempDir() {
    std::string t = (std::filesystem::temp_directory_path() / "lockstep-povray-XXXXXX").string();
    if (!::mkdtemp(t.data())) throw std::runtime_error("povray row: cannot make a temporary folder");
    path = t;
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
};

// Runs program with args in dir (POV-Ray's I/O restrictions allow the current
// folder), its stdout and stderr into dir/log; returns the exit status and the log.
int run_process(const std::string& dir, const std::vector<std::string>& args, std::string& log) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const std::string log_path = dir + "/log";
  const pid_t pid = ::fork();
  if (pid < 0) throw std::runtime_error("povray row: fork failed");
  if (pid == 0) {
    if (::chdir(dir.c_str()) != 0) ::_exit(126);
    const int fd = ::open(log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      ::dup2(fd, 1);
      ::dup2(fd, 2);
      ::close(fd);
    }
    const int null = ::open("/dev/null", O_RDONLY);
    if (null >= 0) ::dup2(null, 0);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) throw std::runtime_error("povray row: waitpid failed");
  std::ifstream f(log_path);
  log.assign((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

std::string ms(double s) {
  char b[32];
  std::snprintf(b, sizeof b, "%.1f ms", 1e3 * s);
  return b;
}

// An upper bound on any pixel's value, rounded up to a power of 2 (at least
// 1, at most kMaxScale): P_1 = max(background, L), P_k = max(background,
// L + r P_(k-1)), with L the largest local term (ambient + every light's
// diffuse and specular at full strength) and r the largest kr + kt.
constexpr double kMaxScale = 16;
double exposure_scale(const Scene& s, const TraceSettings& t) {
  const double default_ip = s.lights.empty() ? 1.0 : 1.0 / std::sqrt(double(s.lights.size()));
  double local = 0, r = 0;
  for (const Material& m : s.materials) {
    const double c = std::max({m.color.x, m.color.y, m.color.z, 0.0});
    double l = kAmbient * m.kd * c;
    for (const Light& li : s.lights) {
      const double ip = li.has_color ? std::max({li.color.x, li.color.y, li.color.z, 0.0}) : default_ip;
      l += ip * (m.kd * c + std::max(0.0, m.ks));
    }
    local = std::max(local, l);
    r = std::max(r, std::min(1.0, std::max(0.0, m.ks)) + std::min(1.0, std::max(0.0, m.transmittance)));
  }
  const double bg = std::max({s.background.x, s.background.y, s.background.z, 0.0});
  double p = std::max(bg, local);
  for (int k = 2; k <= t.max_depth && p <= kMaxScale; ++k) p = std::max(bg, local + r * p);
  double scale = 1;
  while (scale < p && scale < kMaxScale) scale *= 2;
  return scale;
}

}  // namespace

std::string scene_text(const Scene& s, const FrameOptions& o) {
  check_lights(s);
  const TraceSettings t = trace_settings(o.params, "settings");
  // Every light, the ambient light and the background at 1/scale (POV-Ray
  // clips its output to [0, 1]; every term is linear in them), scaled back
  // when the image is read.
  const double inv = 1.0 / exposure_scale(s, t);
  const Camera cam = Camera::from_view(s.view, o.width, o.height);
  std::ostringstream out;
  out << "// written by lockstep's povray row (optimized/ray_trace_povray.cpp) from " << s.source << "\n";
  out << "#version 3.7;\n";
  out << "global_settings { assumed_gamma 1.0 ambient_light rgb " << num(inv) << " max_trace_level " << t.max_depth
      << " adc_bailout " << num(t.cutoff) << " }\n";
  out << "background { rgb " << vec(inv * s.background) << " }\n";
  // Pixel (x, y)'s ray: direction + ((x+1/2)/W - 1/2) right + (1/2 - (y+1/2)/H) up (see above).
  out << "camera { perspective location " << vec(cam.eye) << " direction " << vec(cam.forward) << " right "
      << vec(double(o.width) * cam.pitch * cam.right) << " up " << vec(double(o.height) * cam.pitch * cam.up)
      << " }\n";
  const double default_ip = s.lights.empty() ? 1.0 : 1.0 / std::sqrt(double(s.lights.size()));
  for (const Light& l : s.lights) {
    const Vec3 ip = inv * (l.has_color ? l.color : Vec3{default_ip, default_ip, default_ip});
    out << "light_source { " << vec(l.position) << " color rgb " << vec(ip) << " }\n";
  }
  for (size_t k = 0; k < s.materials.size(); ++k) {
    const Material& m = s.materials[k];
    const double kt = std::min(1.0, m.transmittance), kr = std::min(1.0, m.ks);
    // POV-Ray scales a surface's ambient and diffuse terms by its opacity
    // 1 - T; the tracer's local term is not scaled: undone here (T < 1).
    const double undo = kt < 1 ? 1.0 / (1.0 - kt) : 1.0;
    out << "#declare M" << k << " = texture { pigment { rgbt <" << num(m.color.x) << "," << num(m.color.y) << ","
        << num(m.color.z) << "," << num(kt) << "> } finish { ambient " << num(kAmbient * m.kd * undo)
        << " diffuse " << num(m.kd * undo);
    if (m.ks > 0) out << " phong " << num(m.ks) << " phong_size " << num(m.shine) << " reflection { " << num(kr) << " }";
    out << " } }\n";
  }
  // shadows=none: no object casts a shadow (no_shadow; a shadowless light
  // would also lose its highlights).
  const std::string no_shadow = t.shadows ? "" : " no_shadow";
  auto interior = [&](uint32_t mat) {
    const Material& m = s.materials[mat];
    return (m.transmittance > 0 ? " interior { ior " + num(m.ior) + " }" : std::string()) + no_shadow;
  };
  for (uint32_t i = 0; i < s.sphere_count(); ++i)
    out << "sphere { " << vec(s.sphere_center[i]) << ", " << num(std::abs(s.sphere_radius[i])) << " texture { M"
        << s.sphere_material[i] << " }" << interior(s.sphere_material[i]) << " }\n";
  for (uint32_t c = 0; c < s.cone_count(); ++c) {
    const uint32_t mat = s.cone_material[c];
    if (s.cone_r0[c] == s.cone_r1[c])
      out << "cylinder { " << vec(s.cone_base[c]) << ", " << vec(s.cone_apex[c]) << ", " << num(s.cone_r0[c]);
    else
      out << "cone { " << vec(s.cone_base[c]) << ", " << num(s.cone_r0[c]) << ", " << vec(s.cone_apex[c]) << ", "
          << num(s.cone_r1[c]);
    out << " open texture { M" << mat << " }" << interior(mat) << " }\n";
  }
  // Polygons: their triangulation, one mesh per material (a mesh's interior is
  // one, so that transparent polygons keep their own ior).
  std::vector<std::vector<uint32_t>> by_material(s.materials.size());
  for (uint32_t tr = 0; tr < s.triangle_count(); ++tr) by_material[s.poly_material[s.tri_poly[tr]]].push_back(tr);
  for (size_t k = 0; k < by_material.size(); ++k) {
    if (by_material[k].empty()) continue;
    out << "mesh {\n";
    for (uint32_t tr : by_material[k]) {
      const auto& v = s.tri_vertex[tr];
      if (s.poly_is_patch[s.tri_poly[tr]])
        out << " smooth_triangle { " << vec(s.vertex[v[0]]) << "," << vec(s.vertex_normal[v[0]]) << ","
            << vec(s.vertex[v[1]]) << "," << vec(s.vertex_normal[v[1]]) << "," << vec(s.vertex[v[2]]) << ","
            << vec(s.vertex_normal[v[2]]) << " }\n";
      else
        out << " triangle { " << vec(s.vertex[v[0]]) << "," << vec(s.vertex[v[1]]) << "," << vec(s.vertex[v[2]])
            << " }\n";
    }
    out << " texture { M" << k << " }" << interior(uint32_t(k)) << "\n}\n";
  }
  return out.str();
}

Image trace_render(const Scene& scene, const FrameOptions& o, FrameStats* stats) {
  if (!available())
    throw std::runtime_error("the povray row is not available (no povray program found at configure time, or " +
                             program() + " is gone)");
  const std::string text = scene_text(scene, o);  // checks the lights and settings first
  TempDir dir;
  {
    std::ofstream f(dir.path / "scene.pov");
    f << text;
    if (!f) throw std::runtime_error("povray row: cannot write " + (dir.path / "scene.pov").string());
  }
  const int threads = o.threads > 0 ? o.threads : int(std::max(1u, std::thread::hardware_concurrency()));
  const std::vector<std::string> args = {program(),
                                         "+Iscene.pov",
                                         "+Oimage.ppm",
                                         "+FP16",
                                         "+W" + std::to_string(o.width),
                                         "+H" + std::to_string(o.height),
                                         "-A",
                                         "-D",
                                         "-P",
                                         "+WT" + std::to_string(threads),
                                         "File_Gamma=1.0",
                                         "Output_Alpha=off"};
  std::string log;
  const Stopwatch wall;
  const int rc = run_process(dir.path.string(), args, log);
  const double wall_s = wall.seconds();
  if (rc != 0)
    throw std::runtime_error("povray exited with status " + std::to_string(rc) + ": " + tail(log, 1500));
  const double gain = exposure_scale(scene, trace_settings(o.params, "settings"));
  Image img = read_ppm((dir.path / "image.ppm").string(), o.width, o.height, gain);
  if (o.progress) o.progress(1.0);
  if (stats) {
    const double parse = seconds_of(log, "Parse Time"), bound = seconds_of(log, "Bounding Time"),
                 trace = seconds_of(log, "Trace Time");
    stats->build_seconds = std::max(0.0, parse) + std::max(0.0, bound);
    const uint64_t primary = count_of(log, "Rays"), shadow = count_of(log, "Shadow Ray Tests"),
                   reflect = count_of(log, "Reflected Rays"),
                   refract = count_of(log, "Refracted Rays") + count_of(log, "Transmitted Rays");
    stats->counts = {{"primary", primary}, {"shadow", shadow}, {"reflect", reflect}, {"refract", refract}};
    stats->items = primary + shadow + reflect + refract;
    stats->notes.push_back("povray (" + std::to_string(threads) + " threads): parse " + ms(parse) + ", bounding " +
                           ms(bound) + ", trace " + ms(trace) + "; process " + ms(wall_s) + " (start, write, " +
                           "read: " + ms(wall_s - std::max(0.0, parse) - std::max(0.0, bound) -
                                          std::max(0.0, trace)) + ")");
    const Reach r = reach(scene);
    stats->drop("reaches beyond POV-Ray's 1e7 from the eye: hits farther than that are dropped (whole or part)",
                r.beyond);
    stats->drop("scene smaller than 0.1: POV-Ray's tolerances are absolute (hits nearer than 1e-6 along a ray, "
                "shadow blockers nearer than 1e-3)",
                r.tiny);
    stats->drop("coordinates over 168x the scene's size: POV-Ray's single-precision bounding boxes round by "
                "over 1e-5 of the scene (rays may miss)",
                r.far);
  }
  return img;
}

}  // namespace lockstep::opt::povray

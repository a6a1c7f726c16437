// lockstep trace: the ray tree of one pixel (the ray_trace family's
// TracePixelFn, registry/ray_trace_row.h), printed one ray a line, children indented
// under their parent, in the order they were traced.
#include <cstdio>
#include <string>

#include "app/cli.h"
#include "io/nff.h"
#include "registry/ray_trace_row.h"

namespace lockstep::cli {

namespace {

void print_help(const Family& f) {
  std::printf(
      "usage: lockstep trace SCENE --pixel X,Y [--size WxH] [--impl reference|embree] [SETTINGS]\n"
      "\n"
      "Prints the ray tree of pixel (X, Y) (column from the left, row from the top) of the\n"
      "scene's view, as the ray_trace family traces it: each ray's kind (primary, shadow,\n"
      "reflect, refract), origin, direction, what it hits and where (t), its weight (the\n"
      "product of Ks and T down its path), the colour it returns and its contribution to the\n"
      "pixel (weight x colour); shadow rays say which light and whether they are blocked;\n"
      "TIR marks a refracted ray that total internal reflection turned away.\n"
      "\n"
      "  --pixel X,Y     the pixel (required)\n"
      "  --size WxH      the image it belongs to (default: the scene's resolution)\n"
      "  --impl NAME     reference (default) or embree\n");
  for (const ParamSpec& p : f.params) {
    // Appended piece by piece: `"--" + std::string(...)` trips GCC 12's -Wrestrict (a false
    // positive).
    std::string left = "--";
    left += p.name;
    if (!p.flag) {
      left += ' ';
      left += p.values;
    }
    std::printf("  %-26s %s%s%s\n", left.c_str(), std::string(p.help).c_str(),
                p.def.empty() ? "" : "; default ", std::string(p.def).c_str());
  }
  std::printf("\nExit codes: 0 ok, 2 bad usage or bad input.\n");
}

std::string vec(const Vec3& v) {
  char b[100];
  std::snprintf(b, sizeof b, "(%.6g, %.6g, %.6g)", v.x, v.y, v.z);
  return b;
}

std::string prim_name(const Scene& s, uint32_t prim) {
  if (prim < s.sphere_count()) return "sphere " + std::to_string(prim);
  return "polygon " + std::to_string(prim - s.sphere_count());
}

void print_tree(const Scene& scene, const RayTree& tree) {
  std::vector<int> level(tree.nodes.size(), 0);
  for (size_t k = 0; k < tree.nodes.size(); ++k) {
    const RayNode& n = tree.nodes[k];
    level[k] = n.parent < 0 ? 0 : level[size_t(n.parent)] + 1;
    std::string line(size_t(2 * level[k]), ' ');
    line += ray_kind_name(n.kind);
    char b[160];
    std::snprintf(b, sizeof b, " depth %d weight %.6g origin ", n.depth, n.weight);
    line += b + vec(n.origin) + " dir " + vec(n.direction);
    if (n.kind == RayKind::kShadow) {
      std::snprintf(b, sizeof b, " light %u at %.6g: ", n.light, n.tmax);
      line += b;
      if (n.blocked) {
        line += "blocked";
        if (n.hit.hit()) {
          std::snprintf(b, sizeof b, " by %s at t %.9g", prim_name(scene, n.hit.prim).c_str(),
                        n.hit.t);
          line += b;
        }
      } else {
        line += "reaches, adds " + vec(n.color) + " contribution " + vec(n.weight * n.color);
      }
    } else if (n.tir) {
      line += std::string(" TIR (total internal reflection: not traced)");
    } else {
      if (n.kind == RayKind::kRefract) line += n.entering ? " entering" : " leaving";
      if (n.hit.hit()) {
        std::snprintf(b, sizeof b, " hit %s t %.9g", prim_name(scene, n.hit.prim).c_str(), n.hit.t);
        line += b;
      } else {
        line += " miss";
      }
      line += " colour " + vec(n.color) + " contribution " + vec(n.weight * n.color);
    }
    std::printf("%s\n", line.c_str());
  }
}

}  // namespace

int trace_main(Args args) {
  const Family& family = find_family("ray_trace");
  std::string in_path, impl_name = "reference", value;
  int width = 0, height = 0;
  long px = -1, py = -1;
  Params params;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string_view a = args[i];
    if (a == "--help" || a == "-h") {
      print_help(family);
      return kExitOk;
    } else if (take_option(args, i, "--pixel", value)) {
      const size_t comma = value.find(',');
      if (comma == std::string::npos) throw UsageError("--pixel must be X,Y, got '" + value + "'");
      px = parse_long("--pixel X", std::string_view(value).substr(0, comma), 0, kMaxResolution - 1);
      py =
          parse_long("--pixel Y", std::string_view(value).substr(comma + 1), 0, kMaxResolution - 1);
    } else if (take_option(args, i, "--size", value)) {
      parse_size(value, width, height);
    } else if (take_option(args, i, "--impl", value)) {
      impl_name = value;
    } else if (const ParamSpec* p = find_param(family, a)) {
      if (p->flag)
        params.set(std::string(p->name), "1");
      else if (take_option(args, i, a, value))
        params.set(std::string(p->name), value);
    } else if (is_option(a)) {
      unknown_option(a);
    } else if (in_path.empty()) {
      in_path = std::string(a);
    } else {
      throw UsageError("unexpected argument '" + std::string(a) + "' (one scene per call)");
    }
  }
  if (in_path.empty()) throw UsageError("missing SCENE");
  if (px < 0) throw UsageError("missing --pixel X,Y");
  const Impl<TracerFns>* impl = ray_trace_row().find(impl_name);
  if (!impl)
    throw UsageError("--impl: '" + impl_name + "' is not one of " + impl_names(family, "|"));
  TraceSettings settings;
  try {
    settings = trace_settings(params, "settings");
  } catch (const InputError& e) {
    throw UsageError(std::string(e.what()).substr(std::string("settings: ").size()));
  }
  const Scene scene = read_nff(in_path);
  if (width == 0) width = scene.view.xres, height = scene.view.yres;
  if (px >= width || py >= height)
    throw UsageError("--pixel " + std::to_string(px) + "," + std::to_string(py) +
                     " is outside the " + std::to_string(width) + "x" + std::to_string(height) +
                     " image");
  RayTree tree;
  const Vec3 c = impl->fn.pixel(scene, settings, width, height, int(px), int(py), &tree);
  std::printf(
      "%s pixel %ld,%ld of %dx%d, %s, depth %d, shadows %s, cutoff %g: colour %s, %zu rays\n",
      in_path.c_str(), px, py, width, height, impl_name.c_str(), settings.max_depth,
      settings.shadows ? "rays" : "none", settings.cutoff, vec(c).c_str(), tree.nodes.size());
  print_tree(scene, tree);
  return kExitOk;
}

}  // namespace lockstep::cli

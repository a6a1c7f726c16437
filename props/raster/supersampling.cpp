// lockstep props/raster: supersampling against the exact box-filtered image.
//
//   SupersamplingConverges.zbuffer__<impl>   flat-coloured triangles parallel
//       to the image plane (one depth each, so the exact oracle applies:
//       exact_coverage.h), drawn at spp 1, 4, 16 and 64 on the regular and the
//       rotated grid. Each pixel's error against the exact image is bounded:
//       a straight edge crossing the pixel passes through at most 2n of the n x n
//       sample cells, so it misjudges at most 2n/n^2 = 2/n of the pixel's area;
//       snapping moves an edge by at most sqrt(2)/512 pixel, which changes the
//       area by at most sqrt(2) * sqrt(2)/512 = 1/256. So
//           |error| <= e (2/n + 1/256) C,
//       e the number of triangle edges that cross the pixel, C the largest colour
//       difference in the scene. Unexplained: a pixel over its bound.
#include <cmath>
#include <sstream>

#include "io/nff.h"
#include "props/gen/numbers.h"
#include "props/raster/exact_coverage.h"
#include "props/raster/parts.h"
#include "core/raster.h"

namespace lockstep::props::raster {

namespace {

// Whether segment a-b meets the unit square of pixel (i, j) (closed).
bool crosses(double ax, double ay, double bx, double by, int i, int j) {
  // Liang-Barsky clip of the segment against the square.
  double t0 = 0, t1 = 1;
  const double dx = bx - ax, dy = by - ay;
  const double p[4] = {-dx, dx, -dy, dy}, q[4] = {ax - i, i + 1 - ax, ay - j, j + 1 - ay};
  for (int k = 0; k < 4; ++k) {
    if (p[k] == 0) {
      if (q[k] < 0) return false;
    } else {
      const double r = q[k] / p[k];
      if (p[k] < 0) t0 = std::max(t0, r);
      else t1 = std::min(t1, r);
    }
  }
  return t0 <= t1;
}

}  // namespace

rc::Gen<RasterCase> flat_parallel_scene() {
  return rc::gen::exec([] {
    RasterCase c;
    c.width = *rc::gen::inRange(4, 17);
    c.height = *rc::gen::inRange(4, 17);
    std::string s = "v\nfrom 0 0 0\nat 0 0 -1\nup 0 1 0\nangle 40\nhither 1\nresolution " + std::to_string(c.width) +
                    " " + std::to_string(c.height) + "\nb 0.1 0.2 0.3\nl 0 0 10\n";
    const int tris = *rc::gen::inRange(1, 6);
    const double half = std::tan(20.0 * M_PI / 180.0);
    for (int t = 0; t < tris; ++t) {
      const double z = 2 + 2 * t + *gen::uniform(0, 1);  // distinct depths
      s += "f " + num(*gen::uniform(0, 1)) + " " + num(*gen::uniform(0, 1)) + " " + num(*gen::uniform(0, 1)) +
           " 1 0 1 0.5 1\np 3\n";  // two-sided (T > 0): either winding is drawn
      for (int k = 0; k < 3; ++k)
        s += num(*gen::uniform(-1.3, 1.3) * half * z) + " " + num(*gen::uniform(-1.3, 1.3) * half * z) + " " + num(-z) +
             "\n";
    }
    c.nff = s;
    c.params.set("shading", "flat");
    return c;
  });
}

std::vector<FlatTri> flat_tris(const Scene& scene, const ScreenMesh& mesh) {
  const Camera& cam = mesh.camera;
  std::vector<Vec3> color(scene.prim_count());
  for (const ScreenTri& t : mesh.tris) color[t.prim] = t.flat_color;
  std::vector<FlatTri> out;
  for (uint32_t k = 0; k < scene.triangle_count(); ++k) {
    FlatTri f;
    const uint32_t prim = scene.sphere_count() + scene.tri_poly[k];
    f.color = color[prim];
    for (int v = 0; v < 3; ++v) {
      const Vec3 d = scene.vertex[scene.tri_vertex[k][v]] - cam.eye;
      const double ze = dot(d, cam.forward);
      f.x[v] = 0.5 * cam.width + dot(d, cam.right) / (ze * cam.pitch);
      f.y[v] = 0.5 * cam.height - dot(d, cam.up) / (ze * cam.pitch);
      f.depth = ze;
    }
    out.push_back(f);
  }
  return out;
}

namespace {

Verdict converges(const FamilyImpl& impl, const RasterCase& c) {
  const auto scene = c.scene();
  const RasterSettings s0 = raster_settings(c.params, "<case>");
  const ScreenMesh mesh = view_scene(*scene, c.width, c.height, s0);
  const std::vector<FlatTri> tris = flat_tris(*scene, mesh);
  const Image exact = exact_box_filtered(tris, c.width, c.height, scene->background);
  // C: the largest colour difference in the scene (background included).
  double contrast = 0;
  std::vector<Vec3> colors{scene->background};
  for (const FlatTri& t : tris) colors.push_back(t.color);
  for (const Vec3& a : colors)
    for (const Vec3& b : colors)
      for (int k = 0; k < 3; ++k) contrast = std::max(contrast, std::abs(a[k] - b[k]));
  const Input in = make_input<Scene>(*scene, "<case>", c.width, c.height, scene->background);
  Verdict v;
  for (const char* grid : {"regular", "rotated"})
    for (int n : {1, 2, 4, 8}) {
      RasterCase cs = c;
      cs.params.set("spp", std::to_string(n * n));
      cs.params.set("grid", grid);
      FrameStats st;
      const Image img = impl.run_as<Image>(in, cs.options(), &st);
      for (int j = 0; j < c.height; ++j)
        for (int i = 0; i < c.width; ++i) {
          int edges = 0;
          for (const FlatTri& t : tris)
            for (int k = 0; k < 3; ++k)
              edges += crosses(t.x[k], t.y[k], t.x[(k + 1) % 3], t.y[(k + 1) % 3], i, j);
          double err = 0;
          for (int k = 0; k < 3; ++k) err = std::max(err, double(std::abs(img.pixel(i, j)[k] - exact.pixel(i, j)[k])));
          // Colour precision on top: the frame's float rounding (1e-6) and the
          // optimized z-buffer's flat colours, lit in float lanes (FlatColors:
          // a few ulps of the colour: 1.19e-6 on a colour of 1.09 in the
          // counterexample flat_parallel_scene.zbuffer.simd-2; in four deep
          // runs of 1000 cases, interior pixels' errors at most 1.0e-6 of
          // their colour).
          double level = 0;
          for (int k = 0; k < 3; ++k) level = std::max(level, double(std::abs(exact.pixel(i, j)[k])));
          const double bound = edges * (2.0 / n + 1.0 / 256) * contrast + 1e-6 + 1e-6 * level;
          Outcome o;
          o.err = err;
          o.measured = true;
          o.unit = "colour vs exact, spp " + std::to_string(n * n);
          if (err > bound) {
            o.kind = Outcome::unexplained;
            o.label = "over_bound";
            std::ostringstream d;
            d << "pixel (" << i << ", " << j << ") spp " << n * n << " " << grid << ": " << impl.name << " ("
              << img.pixel(i, j)[0] << ", " << img.pixel(i, j)[1] << ", " << img.pixel(i, j)[2] << ") exact ("
              << exact.pixel(i, j)[0] << ", " << exact.pixel(i, j)[1] << ", " << exact.pixel(i, j)[2]
              << "), error " << err << " > bound " << bound << " (" << edges << " edges, contrast " << contrast
              << ")";
            o.detail = d.str();
          }
          v.rays.push_back(o);
        }
    }
  return v;
}

}  // namespace

void supersampling_part(const Family& family, FamilyProperties& out) {
  // Implementations that cannot supersample (llvmpipe: one sample per pixel)
  // say so through their unsupported().
  const Params supersampled{{{"spp", "16"}}};
  for (const FamilyImpl& impl : family.impls)
    if (!impl.unsupported || impl.unsupported(supersampled).empty())
      out.properties.push_back(case_property(family, impl, "SupersamplingConverges", "flat_parallel_scene",
                                             flat_parallel_scene(), 0, "colour",
                                             [&impl](const RasterCase& c) { return converges(impl, c); }));
}

}  // namespace lockstep::props::raster

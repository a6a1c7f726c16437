// lockstep optimized: the z-buffer family's production peer, Mesa's llvmpipe
// software rasteriser through OSMesa (legacy OpenGL, compatibility profile).
//
// The geometry is the reference's: view_scene() tessellates the spheres,
// applies NFF's sidedness and the cull mode, and lights the triangles
// (Shading::kFlat: one colour per triangle; kGouraud: one per vertex). What
// llvmpipe does on its own is everything after that: the vertex transform (in
// float), clipping, its own snapping (8 subpixel bits) and fill rule, depth
// interpolation and the 24-bit depth test, and colour interpolation. So the row
// measures a production rasteriser against the textbook one on the same
// triangles.
//
// The camera (core/camera.h): NFF's angle spans the *centres* of the edge
// pixels, pitch s = 2 tan(angle/2) / (min(W, H) - 1) at distance 1. GL puts
// pixel i's centre at window x = i + 1/2, which is camera x = (i - (W-1)/2) s
// exactly when the frustum's half-width at distance 1 is s W / 2 (and s H / 2
// high). The modelview is the look-at rotation (rows right, up, -forward); the
// translation by -eye is applied in double before the vertices are rounded to
// float, so that a scene far from the origin keeps its digits.
//
// Depth: 24-bit fixed point (OSMesa offers 16 or 24 bits; asking for 32 gives
// 24), GL_LESS, so the first of two equal depths stays, as in the reference.
// The window depth d of eye depth z is
//     d = f/(f-n) (1 - n/z),   z = n f / (f - d (f - n)),
// with n = hither and f a little beyond the scene's far bound (near_plane(),
// far_plane()). Colour: a float RGBA buffer (OSMesaMakeCurrent with GL_FLOAT),
// no clamping anywhere (glClampColor), so colours above 1 survive as in the
// reference; no quantisation. Culling: view_scene has culled per
// RasterSettings::cull and re-oriented what it keeps, so GL culls nothing.
//
// Threads: llvmpipe reads LP_NUM_THREADS once per process, when the first
// context creates its screen (measured: contexts made after changing it keep
// the first count of rasteriser threads). The first Context sets it from
// FrameOptions::threads (1: LP_NUM_THREADS=0, the calling thread bins and
// rasterises; N > 1: N rasteriser threads; 0: all cores) unless the
// environment already has it; a later request for another count is reported
// in FrameStats::notes. So threads=1 and threads=2 need separate processes.
//
// Cost: a context per call (no state outlives zbuffer()), so every call pays
// context creation and LLVM's compilation of the shader variants for this
// state (FrameStats::build_seconds: about 11 ms in the benchmark, 20-50 ms
// cold), and the float colour buffer costs a fixed ~7 ms a frame at 1024^2
// (clear, and OSMesa's copy into the image). tools/llvmpipe_check.cpp
// `time` separates the phases.
#include "core/error.h"
#include "optimized/raster.h"

namespace lockstep::opt::llvmpipe {

namespace {

// What this row can draw: the pre-lit shadings (view_scene lights them), one
// sample per pixel (OSMesa has no multisampling), GL's perspective-correct
// interpolation. Any depth setting: llvmpipe's depth is its own 24-bit buffer.
std::string unsupported(const RasterSettings& s) {
  if (s.shading != Shading::kFlat && s.shading != Shading::kGouraud)
    return "llvmpipe draws only shading=flat or shading=gouraud (lit per triangle or per vertex)";
  if (s.spp != 1) return "llvmpipe draws one sample per pixel (spp=1)";
  if (!s.perspective) return "llvmpipe interpolates perspective-correctly only (no interp=affine)";
  if (s.silhouette) return "llvmpipe does not draw silhouettes";
  return "";
}

}  // namespace

std::string unsupported(const Params& params) {
  try {
    return unsupported(raster_settings(params, "settings"));
  } catch (const InputError&) {
    return "";  // bad settings are the family's to report (check_params, or the render's
                // InputError)
  }
}

}  // namespace lockstep::opt::llvmpipe

#ifdef LOCKSTEP_HAVE_OSMESA

// glClampColor is GL 3.0: its prototype comes from GL/glext.h, which GL/gl.h
// (included by osmesa.h) includes; libOSMesa exports it.
#define GL_GLEXT_PROTOTYPES 1
#include <GL/osmesa.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <thread>

#include "core/timer.h"
#include "optimized/raster_llvmpipe.h"

namespace lockstep::opt::llvmpipe {

namespace {

// The LP_NUM_THREADS value for FrameOptions::threads: 1 means one thread does
// everything (llvmpipe's 0: the calling thread rasterises, no worker threads);
// N > 1 is N rasteriser threads (the calling thread bins); 0 is all cores.
std::string lp_threads_for(int threads) {
  if (threads == 0) threads = int(std::thread::hardware_concurrency());
  return threads <= 1 ? "0" : std::to_string(threads);
}

}  // namespace

double far_plane(double near_z, double far_z) {
  if (!(far_z > near_z)) return 2 * near_z;
  // At z = far_z, 1 - d = n e / (f - n) for f = far_z (1 + e): e keeps that at
  // least 2^-20, sixteen steps of the 24-bit buffer.
  const double e = std::max(1e-3, 0x1p-20 * far_z / near_z);
  return far_z * (1 + e);
}

double near_plane(double hither) { return hither * (1 - 0x1p-20); }

double depth_step(double z, double near_z, double far_z) {
  const double n = near_plane(near_z), f = far_plane(near_z, far_z);
  // d = f/(f-n) (1 - n/z): dz/dd = z^2 (f - n) / (n f).
  return 0x1p-24 * z * z * (f - n) / (n * f);
}

struct Context::State {
  OSMesaContext ctx = nullptr;
  int width = 0, height = 0;
  bool compiled = false;                // the first draw has been warmed up
  std::vector<float> vertices, colors;  // the arrays GL reads (client-side vertex arrays)
  std::vector<float> window_depth;      // glReadPixels' depth, bottom row first
};

Context::Context(int width, int height, int threads, std::vector<std::string>* notes)
    : st_(new State) {
  const Stopwatch clock;
  // The thread count must be in the environment before llvmpipe's screen exists.
  const std::string want = lp_threads_for(threads);
  const char* have = std::getenv("LP_NUM_THREADS");
  if (have == nullptr) {
    setenv("LP_NUM_THREADS", want.c_str(), 0);
    have = std::getenv("LP_NUM_THREADS");
  } else if (want != have && notes) {
    notes->push_back(
        "llvmpipe: LP_NUM_THREADS=" + std::string(have) +
        " (from the environment, or an earlier frame of this process: llvmpipe reads it once, at "
        "its first context) overrides threads=" +
        std::to_string(threads) + " (LP_NUM_THREADS=" + want + "); run it in a process of its own");
  }
  threads_ = have ? have : "";

  st_->width = width;
  st_->height = height;
  // RGBA, 24 depth bits, no stencil, no accumulation buffer.
  st_->ctx = OSMesaCreateContextExt(OSMESA_RGBA, 24, 0, 0, nullptr);
  if (st_->ctx == nullptr) throw std::runtime_error("llvmpipe: OSMesaCreateContextExt failed");
  create_seconds_ = clock.seconds();
}

Context::~Context() {
  if (st_->ctx) OSMesaDestroyContext(st_->ctx);
}

void Context::draw(const ScreenMesh& mesh, const Vec3& background, const RasterSettings& s,
                   Image& img, DrawTimes* times) {
  State& st = *st_;
  DrawTimes t;
  const int W = st.width, H = st.height;
  if (mesh.width != W || mesh.height != H)
    throw std::logic_error("llvmpipe: mesh size differs from the context's");

  // Colour goes straight into the image: float RGBA, row 0 at the top
  // (OSMESA_Y_UP = 0), colours neither clamped on the vertices nor in the buffer.
  if (img.width != W || img.height != H || img.rgba.size() != size_t(W) * size_t(H) * 4)
    img = Image::uninitialized(W, H);
  if (!OSMesaMakeCurrent(st.ctx, img.rgba.data(), GL_FLOAT, W, H))
    throw std::runtime_error("llvmpipe: OSMesaMakeCurrent (float RGBA) failed");
  OSMesaPixelStore(OSMESA_Y_UP, 0);
  glClampColor(GL_CLAMP_VERTEX_COLOR, GL_FALSE);
  glClampColor(GL_CLAMP_FRAGMENT_COLOR, GL_FALSE);
  glClampColor(GL_CLAMP_READ_COLOR, GL_FALSE);
  glDisable(GL_DITHER);
  glDisable(GL_LIGHTING);   // the colours are lit already
  glDisable(GL_CULL_FACE);  // view_scene culled per RasterSettings::cull; what is left is all drawn
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthRange(0.0, 1.0);
  glClearDepth(1.0);
  glClearColor(GLfloat(background.x), GLfloat(background.y), GLfloat(background.z), 1.0f);
  glViewport(0, 0, W, H);

  // Projection: the frustum of core/camera.h's pixel centres (see the header comment).
  const Camera& cam = mesh.camera;
  const double n = near_plane(mesh.near_z);
  const double f = far_plane(mesh.near_z, mesh.far_z);
  const double half_w = n * cam.pitch * 0.5 * W, half_h = n * cam.pitch * 0.5 * H;
  glMatrixMode(GL_PROJECTION);
  glLoadIdentity();
  glFrustum(-half_w, half_w, -half_h, half_h, n, f);
  // Modelview: the look-at rotation; GL's eye looks down -z. Column-major.
  // clang-format off
  const GLdouble look[16] = {cam.right.x, cam.up.x, -cam.forward.x, 0,
                             cam.right.y, cam.up.y, -cam.forward.y, 0,
                             cam.right.z, cam.up.z, -cam.forward.z, 0,
                             0,           0,        0,              1};
  // clang-format on
  glMatrixMode(GL_MODELVIEW);
  glLoadMatrixd(look);

  // Shading: flat takes the provoking (last) vertex's colour, which is the
  // triangle's flat_color on all three; Gouraud interpolates the vertex colours.
  glShadeModel(s.shading == Shading::kFlat ? GL_FLAT : GL_SMOOTH);

  // The vertex arrays: positions relative to the eye (double, then float).
  Stopwatch clock;
  const size_t nv = mesh.tris.size() * 3;
  st.vertices.resize(nv * 3);
  st.colors.resize(nv * 3);
  float* p = st.vertices.data();
  float* c = st.colors.data();
  for (const ScreenTri& tri : mesh.tris) {
    for (const ScreenVertex& v : tri.v) {
      const Vec3 e = v.world - cam.eye;
      const Vec3& col = s.shading == Shading::kFlat ? tri.flat_color : v.color;
      *p++ = float(e.x), *p++ = float(e.y), *p++ = float(e.z);
      *c++ = float(col.x), *c++ = float(col.y), *c++ = float(col.z);
    }
  }
  glEnableClientState(GL_VERTEX_ARRAY);
  glEnableClientState(GL_COLOR_ARRAY);
  glVertexPointer(3, GL_FLOAT, 0, st.vertices.data());
  glColorPointer(3, GL_FLOAT, 0, st.colors.data());
  t.upload = clock.seconds();

  // The first draw of a context compiles llvmpipe's shader variants for this
  // state (LLVM, tens of milliseconds): one triangle, then cleared again.
  if (!st.compiled && nv > 0) {
    clock.restart();
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glFinish();
    t.compile = clock.seconds();
    st.compiled = true;
  }

  clock.restart();
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  if (nv > 0) glDrawArrays(GL_TRIANGLES, 0, GLsizei(nv));
  glFinish();  // OSMesa copies the colour buffer into img here
  t.draw = clock.seconds();

  // Depth: window depth back to eye z (+inf where nothing was drawn), flipped
  // to row 0 at the top.
  clock.restart();
  st.window_depth.resize(size_t(W) * size_t(H));
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, W, H, GL_DEPTH_COMPONENT, GL_FLOAT, st.window_depth.data());
  img.depth.resize(size_t(W) * size_t(H));
  const double k = f - n;
  for (int y = 0; y < H; ++y) {
    const float* src = st.window_depth.data() + size_t(H - 1 - y) * size_t(W);
    float* dst = img.depth.data() + size_t(y) * size_t(W);
    for (int x = 0; x < W; ++x) {
      const double d = src[x];
      dst[x] = d >= 1.0 ? std::numeric_limits<float>::infinity() : float(n * f / (f - d * k));
    }
  }
  t.readback = clock.seconds();

  const GLenum err = glGetError();
  // Release the context: OSMesa would otherwise write into img's pixels again
  // when it is next made current or destroyed, perhaps after img is gone.
  OSMesaMakeCurrent(nullptr, nullptr, GL_FLOAT, 0, 0);
  if (err != GL_NO_ERROR) throw std::runtime_error("llvmpipe: GL error " + std::to_string(err));
  if (times) *times = t;
}

std::string Context::renderer() {
  std::vector<float> px(4);
  if (!OSMesaMakeCurrent(st_->ctx, px.data(), GL_FLOAT, 1, 1))
    return "llvmpipe: OSMesaMakeCurrent failed";
  auto str = [](GLenum name) {
    const GLubyte* v = glGetString(name);
    return v ? std::string(reinterpret_cast<const char*>(v)) : std::string("?");
  };
  const std::string r = str(GL_RENDERER) + ", OpenGL " + str(GL_VERSION);
  OSMesaMakeCurrent(nullptr, nullptr, GL_FLOAT, 0, 0);
  return r;
}

bool available() { return true; }

std::string version() {
  // The strings need a current context. It makes llvmpipe's screen, with all
  // cores unless LP_NUM_THREADS says otherwise (the CLI's --version is a process of its own).
  Context ctx(1, 1, 0, nullptr);
  return ctx.renderer() + ", LP_NUM_THREADS=" + ctx.thread_count();
}

Image zbuffer(const Scene& scene, const FrameOptions& opts, FrameStats* stats) {
  const RasterSettings s = frame_settings(scene, opts);  // as every raster row: at most 2^25 samples
  if (const std::string why = unsupported(s); !why.empty()) throw InputError(scene.source, 0, why);
  const ScreenMesh mesh = view_scene(scene, opts.width, opts.height, s);
  std::vector<std::string> notes;
  Context ctx(opts.width, opts.height, opts.threads, &notes);
  DrawTimes t;
  Image img;
  ctx.draw(mesh, scene.background, s, img, &t);
  if (stats) {
    stats->build_seconds = ctx.create_seconds() + t.compile;
    stats->items = mesh.scene_tris + mesh.sphere_tris;  // as the reference counts

    for (std::string& line : notes) stats->notes.push_back(std::move(line));
  }
  return img;
}

}  // namespace lockstep::opt::llvmpipe

#else  // no OSMesa: the row is not registered (pairs/raster.cpp asks available()).

#include <stdexcept>

namespace lockstep::opt::llvmpipe {

bool available() { return false; }
std::string version() { return {}; }
Image zbuffer(const Scene& scene, const FrameOptions&, FrameStats*) {
  throw InputError(scene.source, 0,
                   "llvmpipe: this build has no OSMesa (install libosmesa6-dev and re-run cmake)");
}

}  // namespace lockstep::opt::llvmpipe

#endif

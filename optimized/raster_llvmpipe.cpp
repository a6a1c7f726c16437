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
// Cost: zbuffer() makes a context per call, so every call pays context
// creation and LLVM's compilation of the shader variants for this state
// (FrameStats::build_seconds: about 11 ms in the benchmark, 20-50 ms cold).
// A Session keeps its context across frames, as an application keeps its GL
// context: only its first frame pays that (the row's FamilyImpl::session, so
// the benchmarks time llvmpipe as its users run it, its cold first frame in
// first_ms). The float colour buffer costs a fixed ~7 ms a frame at 1024^2
// (clear, and OSMesa's copy into the image). bench/timing/llvmpipe_check.cpp
// `time` separates the phases.
//
// Module: the GL calls are in optimized/raster_llvmpipe_module.cpp, built as
// lockstep_peer_llvmpipe.so and opened by the first Context of the process
// (optimized/peer_module.h); the rest of the binary does not link libOSMesa.
#include "optimized/raster_llvmpipe.h"

#include "core/error.h"
#include "optimized/zbuffer/zbuffer_llvmpipe.h"

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
  if (s.shadows != ShadowMode::kNone) return "llvmpipe draws no shadows (shadows=none only)";
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

#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <thread>

#include "core/timer.h"
#include "optimized/peer_module.h"
#include "optimized/raster_llvmpipe.h"
#include "optimized/zbuffer/zbuffer_simd.h"

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

Context::Context(int width, int height, int threads, std::vector<std::string>* notes)
    : width_(width), height_(height) {
  const Stopwatch clock;
  // Opening the module (libOSMesa, LLVM) is part of the context's one-shot cost.
  api_ = static_cast<const ModuleApi*>(peer::open_api("llvmpipe", kAbi));
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
  handle_ = api_->create(width, height);
  create_seconds_ = clock.seconds();
}

Context::~Context() {
  if (handle_) api_->destroy(handle_);
}

void Context::draw(const ScreenMesh& mesh, const Vec3& background, const RasterSettings& s,
                   Image& img, DrawTimes* times) {
  if (mesh.width != width_ || mesh.height != height_)
    throw std::logic_error("llvmpipe: mesh size differs from the context's");
  if (img.width != width_ || img.height != height_ ||
      img.rgba.size() != size_t(width_) * size_t(height_) * 4)
    img = Image::uninitialized(width_, height_);
  DrawSetup setup;
  setup.near_plane = near_plane(mesh.near_z);
  setup.far_plane = far_plane(mesh.near_z, mesh.far_z);
  setup.flat = s.shading == Shading::kFlat;
  api_->draw(handle_, mesh, background, setup, img, times);
}

void Context::draw_texture(const TextureScene& scene, const TextureFilterSettings& filter, Image& img,
                           DrawTimes* times) {
  if (img.width != width_ || img.height != height_ || img.rgba.size() != size_t(width_) * size_t(height_) * 4)
    img = Image::uninitialized(width_, height_);
  const Camera cam = Camera::from_view(scene.view, width_, height_);
  TextureDraw q;
  const Vec3 corner[4] = {scene.origin, scene.origin + scene.edge_s, scene.origin + scene.edge_s + scene.edge_t,
                          scene.origin + scene.edge_t};
  const double st[4][2] = {{0, 0}, {scene.repeat_u, 0}, {scene.repeat_u, scene.repeat_v}, {0, scene.repeat_v}};
  double far_z = 0;
  for (int k = 0; k < 4; ++k) {
    const Vec3 e = corner[k] - cam.eye;
    q.corners[k][0] = float(e.x);
    q.corners[k][1] = float(e.y);
    q.corners[k][2] = float(e.z);
    q.st[k][0] = float(st[k][0]);
    q.st[k][1] = float(st[k][1]);
    far_z = std::max(far_z, dot(e, cam.forward));
  }
  // GL enums (GL/gl.h is the module's): NEAREST 0x2600, LINEAR 0x2601,
  // LINEAR_MIPMAP_NEAREST 0x2701, LINEAR_MIPMAP_LINEAR 0x2703; REPEAT 0x2901,
  // CLAMP_TO_EDGE 0x812F, MIRRORED_REPEAT 0x8370.
  q.mag_filter = filter.filter == TextureFilter::point ? 0x2600 : 0x2601;
  switch (filter.filter) {
    case TextureFilter::point: q.min_filter = 0x2600; break;
    case TextureFilter::bilinear: q.min_filter = 0x2601; break;
    case TextureFilter::mip_nearest: q.min_filter = 0x2701; q.mipmaps = true; break;
    default: q.min_filter = 0x2703; q.mipmaps = true; break;
  }
  if (filter.filter == TextureFilter::aniso) q.anisotropy = float(filter.n);
  q.wrap = scene.texture.wrap == Wrap::repeat ? 0x2901 : scene.texture.wrap == Wrap::clamp ? 0x812F : 0x8370;
  DrawSetup setup;
  const double hither = scene.view.hither > 0 ? scene.view.hither : 1e-6;
  setup.near_plane = near_plane(hither);
  setup.far_plane = far_plane(hither, std::max(far_z, 2 * hither));
  api_->draw_texture(handle_, cam, scene.texture, q, setup, scene.background, img, times);
}

std::string Context::renderer() { return api_->renderer(handle_); }

bool available() { return !peer::find_module("llvmpipe").empty(); }

std::string version() {
  // Recorded beside the module when it was built (cmake/peer_version.cpp): the
  // module is not opened here, so --version does not load Mesa and LLVM.
  std::string v = peer::recorded_version("llvmpipe");
  if (v.empty())
    v = "version not recorded (" + peer::module_file("llvmpipe") + " has no .version beside it)";
  const char* lp = std::getenv("LP_NUM_THREADS");
  return v + ", LP_NUM_THREADS=" + (lp ? lp : "unset (all cores)");
}

namespace {

// One frame through ctx, made (or remade for another size) when needed.
// ctx, made (or remade) for opts' frame size when it is not: the seconds
// that took (0 when kept), its notes added to notes.
double fit_context(std::unique_ptr<Context>& ctx, const FrameOptions& opts, std::vector<std::string>& notes) {
  if (ctx && ctx->width() == opts.width && ctx->height() == opts.height) return 0;
  ctx.reset();
  ctx = std::make_unique<Context>(opts.width, opts.height, opts.threads, &notes);
  return ctx->create_seconds();
}

Image draw_frame(std::unique_ptr<Context>& ctx, const Scene& scene, const FrameOptions& opts,
                 FrameStats* stats) {
  const RasterSettings s =
      frame_settings(scene, opts);  // as every raster row: at most 2^25 samples
  if (const std::string why = unsupported(s); !why.empty()) throw InputError(scene.source, 0, why);
  const ScreenMesh mesh = view_scene(scene, opts.width, opts.height, s);
  std::vector<std::string> notes;
  const double create = fit_context(ctx, opts, notes);
  DrawTimes t;
  Image img;
  ctx->draw(mesh, scene.background, s, img, &t);
  if (stats) {
    stats->build_seconds = create + t.compile;          // 0 on a kept context's later frames
    stats->items = mesh.scene_tris + mesh.sphere_tris;  // as the reference counts
    stats->dropped = mesh.dropped;
    // GL's 24-bit depth, d = f/(f-n) (1 - n/z), cleared to 1 and tested with
    // GL_LESS: a triangle whose every vertex rounds to 1 (eye depth beyond
    // about 2^24 hither: far_plane's margin cannot help) is rejected by the
    // depth test. Measured: a plane 1e25 away, drawn by every other row,
    // vanished here. Counted, not hidden (issue #22).
    const double n = near_plane(mesh.near_z), f = far_plane(mesh.near_z, mesh.far_z);
    auto at_far = [&](double z) { return std::nearbyint(f / (f - n) * (1 - n / z) * 0xffffff) >= 0xffffff; };
    uint64_t lost = 0;
    for (const ScreenTri& t : mesh.tris) lost += at_far(t.v[0].z) && at_far(t.v[1].z) && at_far(t.v[2].z);
    stats->drop("24-bit depth rounds to the far plane (eye depth beyond about 2^24 hither): GL_LESS rejects it", lost);
    for (std::string& line : notes) stats->notes.push_back(std::move(line));
  }
  return img;
}

}  // namespace

Image zbuffer(const Scene& scene, const FrameOptions& opts, FrameStats* stats) {
  std::unique_ptr<Context> ctx;
  return draw_frame(ctx, scene, opts, stats);
}

Image Session::zbuffer(const Scene& scene, const FrameOptions& opts, FrameStats* stats) {
  return draw_frame(ctx_, scene, opts, stats);
}

std::string texture_unsupported(const Params& params) {
  TextureFilterSettings f;
  if (!parse_texture_filter(params.get("filter", "trilinear"), f)) return "";
  if (f.filter == TextureFilter::area || f.filter == TextureFilter::super || f.filter == TextureFilter::ewa)
    return "llvmpipe samples with GL's filters only (GL_NEAREST, GL_LINEAR, mipmaps, anisotropy up to 16): no " +
           f.name;
  if (f.filter == TextureFilter::aniso && f.n > 16) return "llvmpipe's anisotropy is at most 16";
  return "";
}

namespace {

// One textured frame through ctx, made (or remade for another size) when needed.
Image texture_frame(std::unique_ptr<Context>& ctx, const TextureScene& scene, const FrameOptions& opts,
                    FrameStats* stats) {
  const TextureFilterSettings f = texture_filter_settings(opts.params, scene.source);
  if (std::string why = texture_unsupported(opts.params); !why.empty()) throw InputError(scene.source, 0, why);
  std::vector<std::string> notes;
  const double create = fit_context(ctx, opts, notes);
  DrawTimes t;
  Image img;
  ctx->draw_texture(scene, f, img, &t);
  if (opts.progress) opts.progress(1.0);
  if (stats) {
    // The context, the shader compilation and the texture's upload with its
    // mipmaps: one-shot costs, shown apart (0 on a session's later frames but
    // the upload when the texture changes).
    stats->build_seconds = create + t.compile + t.upload;
    const TexelMap map = TexelMap::make(scene, opts.width, opts.height);
    uint64_t n = 0;
    for (int y = 0; y < opts.height; ++y)
      for (int x = 0; x < opts.width; ++x) {
        double a, b;
        n += map.texel_at(x + 0.5, y + 0.5, a, b) && map.on_quad(a, b);
      }
    stats->items = n;  // the pixels that see the quad, as our rows count them
    for (std::string& line : notes) stats->notes.push_back(std::move(line));
  }
  return img;
}

}  // namespace

Image texture_filter(const TextureScene& scene, const FrameOptions& opts, FrameStats* stats) {
  std::unique_ptr<Context> ctx;
  return texture_frame(ctx, scene, opts, stats);
}

Image TextureSession::frame(const TextureScene& scene, const FrameOptions& opts, FrameStats* stats) {
  return texture_frame(ctx_, scene, opts, stats);
}

}  // namespace lockstep::opt::llvmpipe

#else  // no OSMesa: the row is not registered (registry/raster_rows.cpp asks available()).

#include <stdexcept>

namespace lockstep::opt::llvmpipe {

bool available() { return false; }
std::string version() { return {}; }
Image zbuffer(const Scene& scene, const FrameOptions&, FrameStats*) {
  throw InputError(scene.source, 0,
                   "llvmpipe: this build has no OSMesa (install libosmesa6-dev and re-run cmake)");
}
Image Session::zbuffer(const Scene& scene, const FrameOptions& opts, FrameStats* stats) {
  return llvmpipe::zbuffer(scene, opts, stats);
}
std::string texture_unsupported(const Params&) { return ""; }
Image texture_filter(const TextureScene& scene, const FrameOptions&, FrameStats*) {
  throw InputError(scene.source, 0,
                   "llvmpipe: this build has no OSMesa (install libosmesa6-dev and re-run cmake)");
}
Image TextureSession::frame(const TextureScene& scene, const FrameOptions& opts, FrameStats* stats) {
  return llvmpipe::texture_filter(scene, opts, stats);
}

}  // namespace lockstep::opt::llvmpipe

#endif

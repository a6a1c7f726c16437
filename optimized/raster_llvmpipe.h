// lockstep optimized: the llvmpipe row's OpenGL context (only built where
// libOSMesa is found: LOCKSTEP_HAVE_OSMESA). opt::llvmpipe::zbuffer
// (optimized/zbuffer/zbuffer_llvmpipe.h) is one Context and one draw(); a Session keeps one
// Context across frames, as an application keeps its GL context (the row's
// FamilyImpl::session, used by the benchmarks' frame loop), and the hand-run
// timing tool (bench/timing/llvmpipe_check.cpp, `time`) keeps one Context and draws
// many times, to separate the one-shot costs (context, LLVM shader
// compilation) from the frame.
//
// The GL code lives in the module lockstep_peer_llvmpipe.so
// (optimized/raster_llvmpipe_module.cpp, the only code linked against
// libOSMesa), opened on the first Context (optimized/peer_module.h); its table
// of functions is ModuleApi below.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/family.h"
#include "core/image.h"
#include "core/raster.h"
#include "core/texture.h"

namespace lockstep::opt::llvmpipe {

// The planes the row's frustum uses for a ScreenMesh's near_z (hither) and
// far_z. Near is a hair closer than hither: view_scene's hither-clipped vertices
// lie on that plane, and float rounding must not let GL clip them a second time.
// Far is a little beyond far_z, so that the farthest vertex gets a window depth
// below 1 (the cleared value, which GL_LESS would refuse).
double near_plane(double hither);
double far_plane(double near_z, double far_z);
// One step of the 24-bit depth buffer at eye depth z, in eye z (grows as z^2).
double depth_step(double z, double near_z, double far_z);

// Where the time of one draw() went, in seconds.
struct DrawTimes {
  double compile = 0;   // the first draw of this context: a one-triangle draw that makes llvmpipe
                        // compile (LLVM) its setup and fragment shader variants; 0 afterwards
  double upload = 0;    // vertex arrays built from the mesh (CPU, ours)
  double draw = 0;      // glClear + glDrawArrays + glFinish (llvmpipe's binning and rasterisation)
  double readback = 0;  // colour rows flipped into the image, depth read and turned into eye z
};

struct ModuleApi;  // below

// One OSMesa context (Mesa's gallium frontend, driver llvmpipe unless
// GALLIUM_DRIVER says otherwise) with a width x height float RGBA colour buffer
// and a 24-bit depth buffer. Not thread-safe: one context per thread.
class Context {
 public:
  // threads: as FrameOptions::threads. llvmpipe reads LP_NUM_THREADS once per
  // process, when the first context creates its screen; see thread_count().
  // A request the process can no longer honour adds a line to notes.
  Context(int width, int height, int threads, std::vector<std::string>* notes);
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  // Draws mesh (view_scene's output for this size) with s.shading (kFlat or
  // kGouraud) over background into img (made width x height if it is not),
  // with a depth plane (eye z, +inf where empty). GL renders into img's pixels
  // directly; the context is released before draw() returns, so img is the
  // caller's again afterwards.
  void draw(const ScreenMesh& mesh, const Vec3& background, const RasterSettings& s, Image& img,
            DrawTimes* times);

  // The texture family's quad (core/texture.h) with the texture uploaded as
  // GL_RGBA32F, its mipmaps made by glGenerateMipmap, sampled by llvmpipe
  // with the given filter into img (made width x height if it is not); no
  // depth plane. times->compile: the first draw's shader compilation;
  // times->upload: the texture's upload and mipmaps.
  void draw_texture(const TextureScene& scene, const TextureFilterSettings& filter, Image& img, DrawTimes* times);

  // GL_RENDERER and GL_VERSION, e.g. "llvmpipe (LLVM 15.0.6, 256 bits), OpenGL 4.5
  // (Compatibility Profile) Mesa 22.3.6". Leaves no context current.
  std::string renderer();

  double create_seconds() const { return create_seconds_; }
  // llvmpipe's rasteriser threads in this process (LP_NUM_THREADS; 0: the
  // calling thread rasterises), as the environment said when the screen was made.
  std::string thread_count() const { return threads_; }
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  const ModuleApi* api_ = nullptr;
  void* handle_ = nullptr;  // the module's context
  int width_ = 0, height_ = 0;
  double create_seconds_ = 0;
  std::string threads_;
};

// Frames drawn by one Context, made on the first frame (the cold one: context,
// LLVM's compilation of the shader variants) and kept while the size stays.
// Not thread-safe: one Session per thread.
class Session {
 public:
  Image zbuffer(const Scene& scene, const FrameOptions& opts, FrameStats* stats);

 private:
  std::unique_ptr<Context> ctx_;
};

// The texture family's llvmpipe row (registry/texture_row.cpp): the quad drawn
// by a fresh context each frame, sampled by GL's filters (GL_NEAREST,
// GL_LINEAR, GL_LINEAR_MIPMAP_NEAREST, GL_LINEAR_MIPMAP_LINEAR, with
// GL_TEXTURE_MAX_ANISOTROPY up to 16); build_seconds holds the context, the
// shader compilation and the texture's upload with its mipmaps.
Image texture_filter(const TextureScene& scene, const FrameOptions& opts, FrameStats* stats);
std::string texture_unsupported(const Params& params);
// Textured frames through one context, kept while the size stays, the texture
// uploaded once while its texels stay (the row's FamilyImpl::session).
// Not thread-safe: one per thread.
class TextureSession {
 public:
  Image frame(const TextureScene& scene, const FrameOptions& opts, FrameStats* stats);

 private:
  std::unique_ptr<Context> ctx_;
};
bool available();
std::string version();

// The module's table (lockstep_peer_api() in lockstep_peer_llvmpipe.so). Host
// and module come from one build: abi must match kAbi.
struct DrawSetup {
  double near_plane = 0, far_plane = 0;  // near_plane(), far_plane() of the mesh
  bool flat = true;                      // Shading::kFlat (else Gouraud)
};
// The texture family's quad for draw_texture: corners relative to the eye,
// texture coordinates, the GL filter state.
struct TextureDraw {
  float corners[4][3];  // O, O + S, O + S + T, O + T, minus the eye
  float st[4][2];       // (0, 0), (ru, 0), (ru, rv), (0, rv)
  int min_filter = 0, mag_filter = 0;  // GL enums
  float anisotropy = 1;                // GL_TEXTURE_MAX_ANISOTROPY (1: off)
  int wrap = 0;                        // GL_REPEAT, GL_CLAMP_TO_EDGE, GL_MIRRORED_REPEAT
  bool mipmaps = false;
};
struct ModuleApi {
  int abi;
  // A context of width x height; throws std::runtime_error.
  void* (*create)(int width, int height);
  void (*destroy)(void* ctx);
  // Context::draw with img already width x height.
  void (*draw)(void* ctx, const ScreenMesh& mesh, const Vec3& background, const DrawSetup& setup,
               Image& img, DrawTimes* times);
  std::string (*renderer)(void* ctx);
  // Context::draw_texture with img already width x height; camera: the
  // scene's (core/camera.h) at the context's size.
  void (*draw_texture)(void* ctx, const Camera& camera, const Texture& tex, const TextureDraw& quad,
                       const DrawSetup& setup, const Vec3& background, Image& img, DrawTimes* times);
};
inline constexpr int kAbi = 2;

}  // namespace lockstep::opt::llvmpipe

// lockstep optimized: the llvmpipe row's GL code, built as the module
// lockstep_peer_llvmpipe.so (the only code linked against libOSMesa; see
// optimized/peer_module.h). The host side, optimized/raster_llvmpipe.cpp,
// makes the mesh (view_scene), the planes and the image, and calls the
// functions of ModuleApi; what is done here, and why, is described at the
// top of that file. Nothing here calls into lockstep's libraries (the module
// is linked with --no-undefined against libOSMesa and the C++ runtime only).
//
// glClampColor is GL 3.0: its prototype comes from GL/glext.h, which GL/gl.h
// (included by osmesa.h) includes; libOSMesa exports it.
#define GL_GLEXT_PROTOTYPES 1
#include <GL/osmesa.h>

#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/timer.h"
#include "optimized/raster_llvmpipe.h"

namespace lockstep::opt::llvmpipe {
namespace {

struct State {
  OSMesaContext ctx = nullptr;
  int width = 0, height = 0;
  bool compiled = false;                // the first draw has been warmed up
  std::vector<float> vertices, colors;  // the arrays GL reads (client-side vertex arrays)
  std::vector<float> window_depth;      // glReadPixels' depth, bottom row first
  // The texture family's texture, kept across frames of one context while the
  // same texels and mipmap need come again (a session's frames).
  GLuint texture = 0;
  const float* texture_data = nullptr;
  int texture_w = 0, texture_h = 0;
  bool texture_mipmaps = false;
};

// Projection: the frustum of core/camera.h's pixel centres for a W x H frame
// (see the host's header comment); modelview: the look-at rotation, GL's eye
// looking down -z (column-major).
void load_camera(const Camera& cam, double n, double f, int W, int H) {
  const double half_w = n * cam.pitch * 0.5 * W, half_h = n * cam.pitch * 0.5 * H;
  glMatrixMode(GL_PROJECTION);
  glLoadIdentity();
  glFrustum(-half_w, half_w, -half_h, half_h, n, f);
  // clang-format off
  const GLdouble look[16] = {cam.right.x, cam.up.x, -cam.forward.x, 0,
                             cam.right.y, cam.up.y, -cam.forward.y, 0,
                             cam.right.z, cam.up.z, -cam.forward.z, 0,
                             0,           0,        0,              1};
  // clang-format on
  glMatrixMode(GL_MODELVIEW);
  glLoadMatrixd(look);
}

void* create(int width, int height) {
  auto* st = new State;
  st->width = width;
  st->height = height;
  // RGBA, 24 depth bits, no stencil, no accumulation buffer.
  st->ctx = OSMesaCreateContextExt(OSMESA_RGBA, 24, 0, 0, nullptr);
  if (st->ctx == nullptr) {
    delete st;
    throw std::runtime_error("llvmpipe: OSMesaCreateContextExt failed");
  }
  return st;
}

void destroy(void* p) {
  auto* st = static_cast<State*>(p);
  if (st->ctx && st->texture) {
    std::vector<float> px(4);
    if (OSMesaMakeCurrent(st->ctx, px.data(), GL_FLOAT, 1, 1)) {
      glDeleteTextures(1, &st->texture);
      OSMesaMakeCurrent(nullptr, nullptr, GL_FLOAT, 0, 0);
    }
  }
  if (st->ctx) OSMesaDestroyContext(st->ctx);
  delete st;
}

void draw(void* p, const ScreenMesh& mesh, const Vec3& background, const DrawSetup& setup,
          Image& img, DrawTimes* times) {
  State& st = *static_cast<State*>(p);
  DrawTimes t;
  const int W = st.width, H = st.height;
  if (mesh.width != W || mesh.height != H || img.width != W || img.height != H ||
      img.rgba.size() != size_t(W) * size_t(H) * 4)
    throw std::logic_error("llvmpipe: mesh or image size differs from the context's");

  // Colour goes straight into the image: float RGBA, row 0 at the top
  // (OSMESA_Y_UP = 0), colours neither clamped on the vertices nor in the buffer.
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

  const Camera& cam = mesh.camera;
  const double n = setup.near_plane, f = setup.far_plane;
  load_camera(cam, n, f, W, H);

  // Shading: flat takes the provoking (last) vertex's colour, which is the
  // triangle's flat_color on all three; Gouraud interpolates the vertex colours.
  glShadeModel(setup.flat ? GL_FLAT : GL_SMOOTH);

  // The vertex arrays: positions relative to the eye (double, then float).
  Stopwatch clock;
  const size_t nv = mesh.tris.size() * 3;
  st.vertices.resize(nv * 3);
  st.colors.resize(nv * 3);
  float* pv = st.vertices.data();
  float* c = st.colors.data();
  for (const ScreenTri& tri : mesh.tris) {
    for (const ScreenVertex& v : tri.v) {
      const Vec3 e = v.world - cam.eye;
      const Vec3& col = setup.flat ? tri.flat_color : v.color;
      *pv++ = float(e.x), *pv++ = float(e.y), *pv++ = float(e.z);
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

// The texture family's quad: one GL_TRIANGLE_FAN with texture coordinates,
// the texture replacing the fragment's colour; the same frustum as draw().
void draw_texture(void* p, const Camera& cam, const Texture& tex, const TextureDraw& q, const DrawSetup& setup,
                  const Vec3& background, Image& img, DrawTimes* times) {
  State& st = *static_cast<State*>(p);
  DrawTimes t;
  const int W = st.width, H = st.height;
  if (img.width != W || img.height != H || img.rgba.size() != size_t(W) * size_t(H) * 4)
    throw std::logic_error("llvmpipe: image size differs from the context's");
  if (!OSMesaMakeCurrent(st.ctx, img.rgba.data(), GL_FLOAT, W, H))
    throw std::runtime_error("llvmpipe: OSMesaMakeCurrent (float RGBA) failed");
  OSMesaPixelStore(OSMESA_Y_UP, 0);
  glClampColor(GL_CLAMP_VERTEX_COLOR, GL_FALSE);
  glClampColor(GL_CLAMP_FRAGMENT_COLOR, GL_FALSE);
  glClampColor(GL_CLAMP_READ_COLOR, GL_FALSE);
  glDisable(GL_DITHER);
  glDisable(GL_LIGHTING);
  glDisable(GL_CULL_FACE);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glClearColor(GLfloat(background.x), GLfloat(background.y), GLfloat(background.z), 1.0f);
  glViewport(0, 0, W, H);
  load_camera(cam, setup.near_plane, setup.far_plane, W, H);

  Stopwatch clock;
  // The texture: uploaded (with its mipmaps) once per context while the same
  // texels come again, as an application uploads a texture once.
  const bool same = st.texture != 0 && st.texture_data == tex.rgba.data() && st.texture_w == tex.width &&
                    st.texture_h == tex.height && (st.texture_mipmaps || !q.mipmaps);
  if (!same) {
    if (st.texture) glDeleteTextures(1, &st.texture);
    glGenTextures(1, &st.texture);
    glBindTexture(GL_TEXTURE_2D, st.texture);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    // Row 0 of the texture is t = 0.
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, tex.width, tex.height, 0, GL_RGBA, GL_FLOAT, tex.rgba.data());
    if (q.mipmaps) glGenerateMipmap(GL_TEXTURE_2D);
    st.texture_data = tex.rgba.data();
    st.texture_w = tex.width;
    st.texture_h = tex.height;
    st.texture_mipmaps = q.mipmaps;
  }
  glBindTexture(GL_TEXTURE_2D, st.texture);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, q.min_filter);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, q.mag_filter);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, q.wrap);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, q.wrap);
  glTexParameterf(GL_TEXTURE_2D, GL_TEXTURE_MAX_ANISOTROPY_EXT, q.anisotropy);
  glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_REPLACE);
  glEnable(GL_TEXTURE_2D);
  glHint(GL_PERSPECTIVE_CORRECTION_HINT, GL_NICEST);
  t.upload = clock.seconds();

  auto quad = [&] {
    glBegin(GL_TRIANGLE_FAN);
    for (int k = 0; k < 4; ++k) {
      glTexCoord2f(q.st[k][0], q.st[k][1]);
      glVertex3f(q.corners[k][0], q.corners[k][1], q.corners[k][2]);
    }
    glEnd();
  };
  if (!st.compiled) {
    clock.restart();
    glClear(GL_COLOR_BUFFER_BIT);
    quad();
    glFinish();
    t.compile = clock.seconds();
    st.compiled = true;
  }
  clock.restart();
  glClear(GL_COLOR_BUFFER_BIT);
  quad();
  glFinish();
  t.draw = clock.seconds();
  glDisable(GL_TEXTURE_2D);
  const GLenum err = glGetError();
  OSMesaMakeCurrent(nullptr, nullptr, GL_FLOAT, 0, 0);
  if (err != GL_NO_ERROR) throw std::runtime_error("llvmpipe: GL error " + std::to_string(err));
  if (times) *times = t;
}

std::string renderer(void* p) {
  auto* st = static_cast<State*>(p);
  std::vector<float> px(4);
  if (!OSMesaMakeCurrent(st->ctx, px.data(), GL_FLOAT, 1, 1))
    return "llvmpipe: OSMesaMakeCurrent failed";
  auto str = [](GLenum name) {
    const GLubyte* v = glGetString(name);
    return v ? std::string(reinterpret_cast<const char*>(v)) : std::string("?");
  };
  const std::string r = str(GL_RENDERER) + ", OpenGL " + str(GL_VERSION);
  OSMesaMakeCurrent(nullptr, nullptr, GL_FLOAT, 0, 0);
  return r;
}

constexpr ModuleApi kApi = {kAbi, create, destroy, draw, renderer, draw_texture};

}  // namespace
}  // namespace lockstep::opt::llvmpipe

// The module's two entry points (C names, found by dlsym).
extern "C" __attribute__((visibility("default"))) const void* lockstep_peer_api() {
  return &lockstep::opt::llvmpipe::kApi;
}

// For cmake/peer_version.cpp at build time: the string --version prints,
// written into out (size bytes, cut if longer).
extern "C" __attribute__((visibility("default"))) void lockstep_peer_version(char* out,
                                                                             unsigned long size) {
  using namespace lockstep::opt::llvmpipe;
  void* ctx = create(1, 1);
  const std::string v = renderer(ctx);
  destroy(ctx);
  if (size > 0) out[v.copy(out, size - 1)] = '\0';
}

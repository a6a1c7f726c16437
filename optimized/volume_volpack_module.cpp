// lockstep optimized: the volpack row's VolPack calls, built as the module
// lockstep_peer_volpack.so (the only code linked against libvolpack; see
// optimized/peer_module.h and, for what is done and why, the top of
// optimized/volume_volpack.cpp, the host side). Nothing here calls into
// lockstep's libraries (linked with --no-undefined against VolPack only).
#include <volpack.h>

#include <memory>
#include <stdexcept>
#include <string>

#include "core/timer.h"
#include "optimized/volume_volpack.h"

namespace lockstep::opt::volpack {

namespace {

struct ContextDeleter {
  void operator()(vpContext* c) const { vpDestroyContext(c); }
};
using ContextPtr = std::unique_ptr<vpContext, ContextDeleter>;

// Every VolPack call goes through check: an error becomes an exception naming
// the call and VolPack's own words.
void check(vpResult r, const char* call) {
  if (r == VP_OK) return;
  const char* s = vpGetErrorString(r);
  throw std::runtime_error(std::string("VolPack: ") + call + " failed: " +
                           (s ? s : "unknown error") + " (code " + std::to_string(r) + ")");
}

void render(const Request& q, unsigned char* pixels, double* classify_seconds,
            double* render_seconds) {
  const int W = q.width, H = q.height;
  const size_t voxels = size_t(q.nx) * size_t(q.ny) * size_t(q.nz);
  const size_t n = size_t(q.qmax) + 1;
  ContextPtr ctx(vpCreateContext());
  if (!ctx) throw std::runtime_error("VolPack: vpCreateContext failed");
  vpContext* c = ctx.get();
  check(vpSetVolumeSize(c, q.nx, q.ny, q.nz), "vpSetVolumeSize");
  check(vpSetVoxelSize(c, int(sizeof(uint16_t)), 1, 1, 1), "vpSetVoxelSize");
  check(vpSetVoxelField(c, 0, int(sizeof(uint16_t)), 0, q.qmax), "vpSetVoxelField");
  check(vpSetRawVoxels(c, const_cast<uint16_t*>(q.voxels), int(voxels * sizeof(uint16_t)),
                       int(sizeof(uint16_t)), int(sizeof(uint16_t)) * q.nx,
                       int(sizeof(uint16_t)) * q.nx * q.ny),
        "vpSetRawVoxels");
  check(vpSetClassifierTable(c, 0, 0, const_cast<float*>(q.opacity), int(n * sizeof(float))),
        "vpSetClassifierTable");
  check(vpSetLookupShader(c, 3, 1, 0, const_cast<float*>(q.colour), int(3 * n * sizeof(float)), 0,
                          nullptr, 0),
        "vpSetLookupShader");
  check(vpSetd(c, VP_MIN_VOXEL_OPACITY, 0.0), "vpSetd(VP_MIN_VOXEL_OPACITY)");
  Stopwatch clock;
  if (q.path == Path::kClassified) check(vpClassifyVolume(c), "vpClassifyVolume");
  if (q.path == Path::kRawOctree) {
    // Nodes of 4^3 voxels, one range of 16-bit values per node treated as
    // uniform: 1/64 of the value range (the user's guide's advice: small
    // against the transfer function's detail).
    check(vpMinMaxOctreeThreshold(c, 0, q.qmax / 64 > 1 ? q.qmax / 64 : 1),
          "vpMinMaxOctreeThreshold");
    check(vpCreateMinMaxOctree(c, 0, 4), "vpCreateMinMaxOctree");
  }
  *classify_seconds = clock.seconds();
  double M[4][4];
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) M[i][j] = q.model[i][j];
  check(vpCurrentMatrix(c, VP_PROJECT), "vpCurrentMatrix(VP_PROJECT)");
  check(vpIdentityMatrix(c), "vpIdentityMatrix");
  check(vpCurrentMatrix(c, VP_VIEW), "vpCurrentMatrix(VP_VIEW)");
  check(vpIdentityMatrix(c), "vpIdentityMatrix");
  check(vpCurrentMatrix(c, VP_MODEL), "vpCurrentMatrix(VP_MODEL)");
  check(vpSetMatrix(c, M), "vpSetMatrix");
  check(vpSetd(c, VP_MAX_RAY_OPACITY, q.max_ray_opacity), "vpSetd(VP_MAX_RAY_OPACITY)");
  check(vpSetImage(c, pixels, W, H, W * 4, VP_RGBA), "vpSetImage");
  clock.restart();
  if (q.path == Path::kClassified)
    check(vpRenderClassifiedVolume(c), "vpRenderClassifiedVolume");
  else
    check(vpRenderRawVolume(c), "vpRenderRawVolume");
  *render_seconds = clock.seconds();
}

constexpr ModuleApi kApi = {kAbi, VP_MAX_VOLUME_DIM, render};

}  // namespace
}  // namespace lockstep::opt::volpack

extern "C" __attribute__((visibility("default"))) const void* lockstep_peer_api() {
  return &lockstep::opt::volpack::kApi;
}

// For cmake/peer_version.cpp at build time: the string --version prints
// (volpack.h's own version string; Debian 12's libvolpack1-dev 1.0b3 says "1.1").
extern "C" __attribute__((visibility("default"))) void lockstep_peer_version(char* out,
                                                                             unsigned long size) {
  const std::string v = std::string("VolPack, volpack.h VP_VERSION ") + VP_VERSION;
  if (size > 0) out[v.copy(out, size - 1)] = '\0';
}

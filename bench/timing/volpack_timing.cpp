// Hand-run timing of the volume family's volpack row (optimized/volume_volpack.h):
// VolPack's three paths on one frame, each run N times, the median of each phase.
//
//   build/bench/lockstep_volpack_timing VOLUME TF VIEW SIZE [N]
//   e.g. build/bench/lockstep_volpack_timing ../shared/volumes/cthead.nhdr ct-bone -90,-15,180 512 5
//
// Paths: classified (the row's: vpClassifyVolume once, vpRenderClassifiedVolume),
// raw (vpRenderRawVolume, classifying as it goes), raw+octree (a min-max octree,
// vpCreateMinMaxOctree, then vpRenderRawVolume). Phases: prepare (our
// quantization and tables), classify (vpClassifyVolume or the octree), render.
// Also the largest difference of the raw paths' images from the classified one.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include "io/volume_io.h"
#include "optimized/volume_volpack.h"

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  using namespace lockstep;
  if (argc < 5) {
    std::fprintf(stderr, "usage: %s VOLUME TF VIEW SIZE [N]\n", argv[0]);
    return 2;
  }
  try {
    if (!opt::volpack::available()) {
      std::fprintf(stderr, "this build has no VolPack\n");
      return 2;
    }
    const Volume v = read_volume(argv[1]);
    FrameOptions o;
    o.width = o.height = std::atoi(argv[4]);
    o.threads = 1;
    o.params.set("tf", argv[2]);
    o.params.set("view", argv[3]);
    const int n = argc > 5 ? std::max(1, std::atoi(argv[5])) : 5;
    std::printf("%s %dx%dx%d, tf %s, view %s, %d^2, %d runs, medians (ms); %s\n", argv[1], v.nx, v.ny, v.nz, argv[2],
                argv[3], o.width, n, opt::volpack::version().c_str());
    Image first;
    const char* names[] = {"classified", "raw", "raw+octree"};
    int k = 0;
    for (const auto path : {opt::volpack::Path::kClassified, opt::volpack::Path::kRaw, opt::volpack::Path::kRawOctree}) {
      std::vector<double> prep, cls, ren;
      Image img;
      for (int i = 0; i < n; ++i) {
        opt::volpack::Times t;
        img = opt::volpack::render_path(v, o, path, &t);
        prep.push_back(t.prepare);
        cls.push_back(t.classify);
        ren.push_back(t.render);
      }
      double diff = 0;
      if (k == 0) first = img;
      else
        for (size_t i = 0; i < img.rgba.size(); ++i) diff = std::max(diff, double(std::abs(img.rgba[i] - first.rgba[i])));
      std::printf("  %-10s prepare %7.2f  classify %7.2f  render %7.2f%s\n", names[k], 1e3 * median(prep),
                  1e3 * median(cls), 1e3 * median(ren),
                  k == 0 ? "" : ("   max |difference| from classified " + std::to_string(diff)).c_str());
      ++k;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
  return 0;
}

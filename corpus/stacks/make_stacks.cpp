// lockstep: writes the small corpus layer stacks of corpus/stacks/ (generated,
// deterministic, credit-free). See corpus/stacks/README.md.
//
//   ninja -C build lockstep_make_stacks && build/lockstep_make_stacks corpus/stacks
//
// PNG layers are straight alpha, written as 8-bit values with the
// `oiio:UnassociatedAlpha` attribute (so OIIO does not un-premultiply them on
// the way out); EXR layers are premultiplied 32-bit float, zip-compressed.
#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "reference/synthetic_stack.h"
#include "io/image_io.h"

namespace {

namespace fs = std::filesystem;
using lockstep::Alpha;
using lockstep::Image;
using lockstep::LayerStack;
using lockstep::Storage;

void write_file(const fs::path& p, const OIIO::ImageSpec& spec, OIIO::TypeDesc type,
                const void* data) {
  auto out = OIIO::ImageOutput::create(p.string());
  if (!out || !out->open(p.string(), spec) || !out->write_image(type, data) || !out->close()) {
    std::fprintf(stderr, "%s: cannot write: %s\n", p.string().c_str(), OIIO::geterror().c_str());
    std::exit(1);
  }
}

// A straight-alpha float image as an 8-bit PNG (round(v * 255), clamped).
void write_png(const Image& img, const fs::path& p) {
  std::vector<uint8_t> q(img.rgba.size());
  for (size_t i = 0; i < q.size(); ++i) {
    const float v = std::min(1.0f, std::max(0.0f, img.rgba[i]));
    q[i] = uint8_t(std::lround(v * 255.0f));
  }
  OIIO::ImageSpec spec(img.width, img.height, 4, OIIO::TypeDesc::UINT8);
  spec.alpha_channel = 3;
  spec.attribute("oiio:UnassociatedAlpha", 1);
  write_file(p, spec, OIIO::TypeDesc::UINT8, q.data());
}

// A premultiplied float image as a 32-bit float EXR.
void write_exr(const Image& img, const fs::path& p) {
  OIIO::ImageSpec spec(img.width, img.height, 4, OIIO::TypeDesc::FLOAT);
  spec.alpha_channel = 3;
  spec.attribute("compression", "zip");
  write_file(p, spec, OIIO::TypeDesc::FLOAT, img.rgba.data());
}

void write_stack(const fs::path& p, const std::string& header,
                 const std::vector<std::string>& files) {
  std::ofstream f(p);
  f << header;
  for (const auto& name : files) f << name << "\n";
  if (!f) {
    std::fprintf(stderr, "%s: cannot write\n", p.string().c_str());
    std::exit(1);
  }
}

std::vector<std::string> write_layers(const LayerStack& s, const fs::path& dir,
                                      const std::string& prefix, bool png) {
  std::vector<std::string> names;
  for (size_t l = 0; l < s.layers.size(); ++l) {
    const std::string name = prefix + "-" + std::to_string(l) + (png ? ".png" : ".exr");
    if (png) {
      write_png(s.layers[l].image, dir / name);
    } else {
      write_exr(s.layers[l].image, dir / name);
    }
    names.push_back(name);
  }
  return names;
}

// Alpha edge cases: stripes of alpha 0, 1, tiny (1e-7, 1e-30, the smallest
// normal), just below 1 and 1/2, with colour everywhere (a straight pixel of
// alpha 0 still has a colour in the file: it must not show).
Image edge_layer(int n, int shift, bool premultiplied) {
  const float alphas[] = {0.0f, 1.0f, 1e-7f, 1e-30f, 1.17549435e-38f, 0.99999994f, 0.5f, 0.0f};
  Image img(n, n);
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      const float a = alphas[((x / 8) + shift * (y / 8)) % 8];
      const float c[3] = {float(x) / float(n - 1), float(y) / float(n - 1),
                          float((x + y) % 17) / 16.0f};
      float* p = img.pixel(x, y);
      for (int k = 0; k < 3; ++k) p[k] = premultiplied ? c[k] * a : c[k];
      p[3] = a;
    }
  }
  return img;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUTPUT_DIR   (e.g. corpus/stacks)\n", argv[0]);
    return 2;
  }
  const fs::path dir = argv[1];
  fs::create_directories(dir);

  // Two straight PNG layers: a translucent front over a mostly opaque back.
  {
    const LayerStack s = lockstep::synthetic_stack(96, 96, 2, 1, Alpha::straight, Storage::f32, 11);
    write_stack(dir / "two-layers.stack", "# Two straight-alpha PNG layers, front first.\n",
                write_layers(s, dir, "two-layers", true));
  }
  // Three premultiplied float EXR layers, composited back to front.
  {
    const LayerStack s =
        lockstep::synthetic_stack(64, 64, 3, -1, Alpha::premultiplied, Storage::f32, 12);
    write_stack(dir / "premult-exr.stack",
                "# Three premultiplied EXR layers, back to front.\norder btf\n",
                write_layers(s, dir, "premult-exr", false));
  }
  // Eight layers, opaque from the third on except a few holes: front-to-back
  // stops early almost everywhere.
  {
    const LayerStack s =
        lockstep::synthetic_stack(128, 128, 8, 2, Alpha::straight, Storage::f32, 13);
    write_stack(dir / "opaque-early.stack",
                "# Eight straight PNG layers, opaque from the third on (except small holes):\n"
                "# front to back stops early over most of the frame.\norder ftb\nearly_stop on\n",
                write_layers(s, dir, "opaque-early", true));
  }
  // Alpha 0, 1 and tiny alphas, straight (PNG) and premultiplied (EXR) mixed.
  {
    write_png(edge_layer(64, 1, false), dir / "alpha-edges-0.png");
    write_exr(edge_layer(64, 3, true), dir / "alpha-edges-1.exr");
    write_png(edge_layer(64, 5, false), dir / "alpha-edges-2.png");
    write_stack(dir / "alpha-edges.stack",
                "# Alpha exactly 0 and 1, tiny alphas (1e-7, 1e-30, smallest normal) and\n"
                "# just below 1; straight PNG and premultiplied EXR layers mixed.\n",
                {"alpha-edges-0.png", "alpha-edges-1.exr", "alpha-edges-2.png"});
  }
  // 8-bit compositing of three straight PNG layers.
  {
    const LayerStack s = lockstep::synthetic_stack(80, 80, 3, 2, Alpha::straight, Storage::f32, 14);
    write_stack(dir / "unorm8.stack",
                "# Three straight PNG layers composited in 8 bits.\nstorage unorm8\n",
                write_layers(s, dir, "unorm8", true));
  }
  std::printf("wrote the corpus stacks to %s\n", dir.string().c_str());
  return 0;
}

// lockstep texture: a texture scene, one filter, one image -- `lockstep render`
// with the family fixed to texture and its texture and wrap mode choosable
// (registry/texture_row.h).
#include <cstdio>

#include "app/cli.h"
#include "core/texture.h"

namespace lockstep::cli {

namespace {

void print_help() {
  std::printf(
      "usage: lockstep texture SCENE [--filter F | --error E] [--texture SPEC] [--wrap W]\n"
      "                        [--impl NAME] [--size WxH] [--threads N] [--repeat N] -o IMAGE\n"
      "\n"
      "Draws SCENE's textured quad under its perspective camera, each pixel the texture\n"
      "filtered over the pixel's footprint (docs/texture.md); the format follows IMAGE's\n"
      "extension (.exr and .tif keep float values, .png 8 bits).\n"
      "\n"
      "  SCENE           a texture scene (.texscene: texture, wrap, quad, repeat, camera;\n"
      "                  corpus/textures/ has a zone plate, a checkerboard to the horizon, a photograph)\n"
      "  --filter F      %s\n"
      "                  (default trilinear; superN: N x N samples a pixel, anisoN: at most N\n"
      "                  probes along the footprint's major axis, ewaN: eccentricity at most N)\n"
      "  --error E       instead of --filter, E in (0, 1]: per tile of 64 x 16 pixels the cheapest of\n"
      "                  point, trilinear, aniso2, aniso4, aniso8, aniso16 whose largest error at 18\n"
      "                  sample pixels of the tile (RGB RMS against area sampling) is at most E, else\n"
      "                  area; the search (lookups at the samples) is the build time, the\n"
      "                  summary names the filters chosen. E bounds the samples, not every pixel.\n"
      "                  reference and simd only\n"
      "  --texture SPEC  the texture in place of the scene's, as the words of a texture line:\n"
      "                  \"checker SIZE CELLS\", \"zoneplate SIZE [K]\", \"noise SIZE SEED\", or\n"
      "                  \"file PATH [srgb|linear]\" (PATH relative to the working directory; 8-bit\n"
      "                  PNG and JPEG are sRGB-decoded unless told linear)\n"
      "  --wrap W        repeat, clamp or mirror, in place of the scene's\n"
      "  --impl NAME     reference, simd (default), oiio (OpenImageIO's TextureSystem) or\n"
      "                  llvmpipe (Mesa's sampler, where it was found at build); the peers have\n"
      "                  no area, superN or EWA (exit 2)\n"
      "  --size WxH      image size (default: the scene's resolution)\n"
      "  --threads N     worker threads, N >= 1 (default: all cores; the reference is single-threaded)\n"
      "  --repeat N      run N times in this process (default 1): the summary gives the last run\n"
      "                  (warm) and the first\n"
      "  -o, --output F  the image to write (required)\n"
      "\n"
      "Prints one summary line on stderr: implementation, size, the pyramid's build time\n"
      "(one-shot), the filtering time, lookups per second, page faults and system time.\n"
      "Exit codes: 0 ok, 2 bad usage or bad input (nothing written), 3 internal error.\n",
      kTextureFilterNames);
}

}  // namespace

int texture_main(Args args) { return render_subcommand("lockstep texture", "texture", args, print_help); }

}  // namespace lockstep::cli

// lockstep radiosity: an NFF scene with emitters, solved for radiosity and
// displayed through the z-buffer -- `lockstep render` with the family fixed
// to radiosity (registry/radiosity_row.h).
#include <cstdio>

#include "app/cli.h"

namespace lockstep::cli {

namespace {

void print_help() {
  std::printf(
      "usage: lockstep radiosity SCENE [--patch-area A] [--error E] [--form-factors rays|hemicube|exact]\n"
      "                          [--rays K] [--hemicube N] [--solver jacobi|gauss-seidel|progressive]\n"
      "                          [--tolerance T] [--impl NAME] [--size WxH] [--threads N] -o IMAGE\n"
      "                          [--patches OUT.ply]\n"
      "\n"
      "Cuts SCENE's polygons into patches, computes the form factors, solves\n"
      "B = E + rho F B and draws the solution through the z-buffer, the vertex\n"
      "radiosities Gouraud-interpolated, without light sources (docs/radiosity.md).\n"
      "The format follows IMAGE's extension (.exr and .tif keep float values, .png 8 bits).\n"
      "\n"
      "  SCENE               an NFF scene (.nff); emitters are polygons after\n"
      "                      '#lockstep emit R G B' (an 'f' line's extension); reflectance is the\n"
      "                      f line's colour x Kd, below 1 (corpus/radiosity/cornell_box.nff)\n"
      "  --patch-area A      the largest patch, in scene units squared (default: the scene's\n"
      "                      polygon area / 256)\n"
      "  --error E           refine: after each solve, cut in four every patch whose radiosity\n"
      "                      jumps from a neighbour's (same polygon) by more than E (0..1) of the\n"
      "                      largest reflected radiosity, the jump weighted by the patch's side\n"
      "                      against the start's; solve again. Patches gather along shadows and\n"
      "                      into corners; --patch-area is the start. At most 4 cuts deep and\n"
      "                      20000 patches (a note says what was left over E). E = 0.05 on the\n"
      "                      Cornell box: 926 patches, a third less largest image error than\n"
      "                      1039 uniform ones\n"
      "  --form-factors M    rays (default): Lambert's factor from each patch's centre times the\n"
      "                      share of K x K rays that reach the other patch; hemicube: the patch's\n"
      "                      view through the z-buffer on five half-cube faces; exact: the\n"
      "                      area-to-area factor (a double contour integral, exact for unoccluded\n"
      "                      patches) times the share of K x K rays that arrive\n"
      "  --rays K            1..16, default 2 (rays and exact)\n"
      "  --hemicube N        pixels a side of the top face, even, 8..1024, default 64\n"
      "  --solver S          gauss-seidel (default), jacobi or progressive (shooting, Cohen et al. 1988)\n"
      "  --tolerance T       stop at a residual of T times the largest emission (default 1e-4)\n"
      "  --impl NAME         reference (single-threaded, brute-force rays) or simd (default:\n"
      "                      Embree's rays, TBB)\n"
      "  --size WxH          image size (default: the scene's resolution)\n"
      "  --threads N         worker threads, N >= 1 (default: all cores)\n"
      "  --repeat N          run N times in this process (default 1)\n"
      "  -o, --output F      the image to write (required)\n"
      "  --patches F         also the patches, as binary PLY (MeshLab, Blender, ParaView open it): each\n"
      "                      patch a face coloured by its radiosity (clamped to 1; float radiosity_r/g/b\n"
      "                      unclamped, int group: its scene polygon), each vertex by the display's\n"
      "                      area-weighted radiosity; scene units\n"
      "\n"
      "Prints one summary line on stderr: implementation, size, time, form factors per second,\n"
      "patches and solver iterations; notes (no emitter, spheres left out, refinement left\n"
      "over E) follow it.\n"
      "Exit codes: 0 ok, 2 bad usage or bad input (nothing written), 3 internal error.\n");
}

}  // namespace

int radiosity_main(Args args) { return render_subcommand("lockstep radiosity", "radiosity", args, print_help); }

}  // namespace lockstep::cli

// lockstep volume: a volume, a transfer function, one image -- `lockstep render`
// with the family chosen among the volume renderers by --algo (registry/volume_rows.h).
#include <cstdio>

#include "app/cli.h"
#include "core/transfer_function.h"

namespace lockstep::cli {

namespace {

void print_help() {
  std::printf(
      "usage: lockstep volume VOLUME --tf TF [--algo raycast|splat|iso] [--step DT] [--eps E] | --error E\n"
      "                       [--view AZ,EL[,ROLL]] [--iso C] [--impl NAME] [--size WxH]\n"
      "                       [--threads N] -o IMAGE\n"
      "\n"
      "Renders VOLUME as a semi-transparent cloud (raycast, splat) or as the surface where\n"
      "its trilinear interpolant equals C (iso), parallel projection; the image is\n"
      "premultiplied RGBA on a transparent background, its format follows IMAGE's extension\n"
      "(.exr and .tif keep float values, .png 8 bits).\n"
      "\n"
      "  VOLUME          a NRRD volume (.nrrd, or a .nhdr header with its data file) or an\n"
      "                  analytic field (.field: sphere, torus, gyroid, marschner_lobb)\n"
      "  --tf TF         the transfer function: a preset (%s) or a .tf file of\n"
      "                  lines 'value r g b alpha', values increasing, colours and alpha in [0, 1],\n"
      "                  alpha per voxel of depth (required for raycast and splat; iso: the colour)\n"
      "  --algo NAME     raycast: V-buffer ray casting, samples every DT, front-to-back over (default)\n"
      "                  splat: each voxel a Gaussian footprint, in depth order\n"
      "                  iso: the first crossing of C along each ray, shaded from the gradient\n"
      "  --iso C         the iso value (iso: required)\n"
      "  --step DT       sampling step along a ray, in voxels, 1/64..16 (default 0.5)\n"
      "  --error E       raycast, instead of --step and --eps: bounds the frame's error against the\n"
      "                  converged image (step 1/16, no early termination): the largest step (4 .. 1/8),\n"
      "                  then the largest eps (1/256 .. 1/65536, else 0), whose mean absolute error per\n"
      "                  channel (RGBA) over the covered pixels (converged alpha > 0; the empty\n"
      "                  background is not counted) is at most E, measured on the frame itself by the\n"
      "                  implementation drawing it (the returned image is the one measured). The\n"
      "                  summary line names the step, eps, error and covered pixels. When even step 1/8\n"
      "                  without termination is over E: exit 2, naming the best error reached.\n"
      "                  Costs about a dozen frames besides (shown as build time); not with volpack\n"
      "  --view AZ,EL[,ROLL]  camera azimuth about z, elevation and roll, degrees (default\n"
      "                  30,20,0; the CT head stands up with -90,-15,180)\n"
      "  --eps E         a ray stops once its opacity reaches 1 - E, 0..0.5 (default 1/256; 0: never;\n"
      "                  --error chooses it)\n"
      "  --impl NAME     implementation (default: simd; see `lockstep render --help`)\n"
      "  --size WxH      image size (default 256x256)\n"
      "  --threads N     worker threads, N >= 1 (default: all cores; the reference is single-threaded)\n"
      "  --repeat N      run N times in this process (default 1): the summary gives the last run\n"
      "                  (warm) and the first\n"
      "  -o, --output F  the image to write (required)\n"
      "\n"
      "Prints one summary line on stderr: implementation, size, seconds, pixels per second (and\n"
      "with --error what it chose).\n"
      "Exit codes: 0 ok, 2 bad usage or bad input (nothing written), 3 internal error.\n",
      transfer_presets());
}

}  // namespace

int volume_main(Args args) { return render_subcommand("lockstep volume", "raycast", args, print_help); }

}  // namespace lockstep::cli

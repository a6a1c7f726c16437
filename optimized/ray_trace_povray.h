// lockstep optimized: the ray-tracing family's production peer, POV-Ray 3.7
// (Debian `povray`), the ray tracer Haines' SPD scenes were written for.
//
// POV-Ray is a program, not a library: the row writes the scene as a .pov
// file into a temporary folder, runs `povray` there as a process with the
// frame's thread count (+WT), and reads its 16-bit PPM back. It is built where
// CMake finds the program (find_program; LOCKSTEP_HAVE_POVRAY, the program's
// path and version recorded at configure time) and available() when that
// program is still there at run time. See optimized/ray_trace_povray.cpp for
// the scene writer, the camera mapping and what POV-Ray draws differently.
#pragma once

#include <string>

#include "core/family.h"
#include "core/image.h"
#include "core/scene.h"

namespace lockstep::opt::povray {

// True when this build has the povray row and the program it found at
// configure time is executable; version() is that program's version as
// `povray --version` said when cmake ran ("POV-Ray 3.7.0.10.unofficial"), and
// program() its path.
bool available();
std::string version();
std::string program();

// The family's contract (core/ray_trace.h; settings depth, cutoff and
// shadows; eps and robust are the tracer's own and do not apply: POV-Ray
// offsets by its own epsilons) drawn by POV-Ray. FrameStats:
//   build_seconds  POV-Ray's parse + bounding time (as it reports them);
//   items, counts  its ray counts (primary, shadow ray tests, reflected,
//                  refracted + transmitted);
//   notes          its parse, bounding and trace times and the process's
//                  wall time, and what it may draw differently in this scene;
//   dropped        what POV-Ray's absolute limits may leave out: primitives
//                  reaching beyond 1e7 from the eye (its MAX_DISTANCE), every
//                  one in a scene smaller than 0.1 (its tolerances are
//                  absolute), those far from the origin for the scene's size
//                  (its single-precision bounding boxes).
// Throws InputError for what it cannot draw the same way (lights with
// lockstep's attenuation or spotlight extension), std::runtime_error when
// the program fails (with the end of its output).
Image trace_render(const Scene& scene, const FrameOptions& options, FrameStats* stats);

// The .pov text trace_render writes for scene at options' size and settings.
std::string scene_text(const Scene& scene, const FrameOptions& options);

}  // namespace lockstep::opt::povray

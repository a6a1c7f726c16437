// lockstep props/ray_trace: the checks, each judging one case of one
// implementation (its TracerRun: frame and one-pixel ray tree) and returning
// one Outcome per judged unit; properties.cpp's header says what each checks.
#pragma once

#include <string>

#include "props/ray_trace/case.h"
#include "props/verdict.h"
#include "registry/ray_trace_row.h"

namespace lockstep::props::ray_trace {

// Laws: reflect() and refract() against the long-double oracle.
Verdict check_laws(const LawCase& c);
// Slab: the leaving ray (the refract node at depth 3) is parallel to the primary.
Verdict check_slab(const TracerRun& fn, const TraceCase& c);
// TIR: the first refract node's tir flag, the reference's, and the oracle's.
Verdict check_tir(const TracerRun& ref, const TracerRun& fn, const TraceCase& c);
// Weights: <= 1 and <= the parent's, along every path of 8 pixels' trees.
Verdict check_weights(const TracerRun& fn, const TraceCase& c);
// Hidden: the frames with and without the objects behind the wall are equal.
Verdict check_hidden(const TracerRun& fn, const TraceCase& c0);
// Pixel: the frame's pixel equals the one-pixel computation's colour, bit for bit.
Verdict check_pixel(const TracerRun& fn, const TraceCase& c);
// Far: every shadow ray of 16 pixels' trees against the exact segment test (oracle.h).
Verdict check_far(const TracerRun& fn, const TraceCase& c, bool textbook);
// Agree: the frame against the reference's, a differing pixel's trees classified.
Verdict check_agree(const TracerRun& ref, const TracerRun& fn, const std::string& known,
                    const TraceCase& c);

}  // namespace lockstep::props::ray_trace

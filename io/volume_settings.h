// lockstep io: the volume families' settings read from their Params
// (core/volume_render.h: vr::Settings and vr::params, the contract). Here, not
// in core, because tf= names a preset or a .tf file, which is read
// (io/transfer_function_io.h).
#pragma once

#include <string>

#include "core/family.h"
#include "core/volume_render.h"

namespace lockstep::vr {

// Throws InputError(source, 0, ...) naming a bad or missing setting (a bad .tf
// file: InputError(file, line, ...)).
Settings settings(const Params& p, const std::string& source, Mode mode);

}  // namespace lockstep::vr

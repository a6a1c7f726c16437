// lockstep io: reading transfer functions -- a preset's name or a .tf file (its
// format and the contract: core/transfer_function.h).
#pragma once

#include <string>

#include "core/transfer_function.h"

namespace lockstep {

// A preset by name, or a .tf file; InputError(path, line, ...) on a bad file,
// InputError(spec, 0, ...) for a name that is neither a preset nor a file.
TransferFunction read_transfer_function(const std::string& spec);
// Parses .tf text (source names it in errors).
TransferFunction parse_transfer_function(std::string_view text, const std::string& source);

}  // namespace lockstep

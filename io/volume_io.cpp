// lockstep io: reading volumes, by extension: NRRD (io/nrrd.cpp) or an
// analytic field (io/field.cpp); see io/volume_io.h.
#include "io/volume_io.h"

#include "core/error.h"
#include "io/text.h"

namespace lockstep {

Volume read_volume(const std::string& path) {
  const std::string ext = text::extension_of(path);
  if (ext == ".field") return sample_field(read_field_spec(path), path);
  if (ext == ".nrrd" || ext == ".nhdr") return read_nrrd(path);
  throw InputError(path, 0, "not a volume: the extension must be .nrrd, .nhdr or .field");
}

}  // namespace lockstep
// lockstep optimized: the VTK peer row of marching cubes (see
// optimized/marching_cubes_vtk.h): Kitware's vtkFlyingEdges3D (Schroeder,
// Maynard, Geveci, LDAV 2015; Debian's libvtk9-dev), run on our Volume and
// turned into our Mesh.
//
//   input   a vtkImageData with our dimensions, spacing and origin whose point
//           scalars are a vtkFloatArray over the Volume's own samples
//           (SetArray with save = 1: zero-copy, VTK never frees or writes them;
//           the const_cast is only for VTK's non-const API). Nothing is copied.
//   filter  one contour value (iso); normals, gradients, scalars and
//           attribute interpolation off (we compare positions and triangles).
//   output  VTK's float points are copied into Mesh::vertices (one memcpy) and
//           its triangle connectivity into Mesh::triangles (flying edges emits
//           only triangles; checked). These two copies are inside the timed run.
//   threads vtkSMPTools' thread count = options.threads for the call (0: VTK's
//           default, all cores), restored afterwards, so no setting outlives
//           it. Debian's VTK 9.1 is built with the TBB, STDThread and
//           Sequential backends and uses TBB unless VTK_SMP_BACKEND_IN_USE says
//           otherwise; version() reports the one in use.
//   orientation  VTK's triangles are counter-clockwise seen from values below
//           the iso value, the opposite of our contract (core/marching_cubes.h),
//           so every triangle's last two corners are swapped. Measured: without
//           the swap Closed and ClosedBelow fail on their first case, the
//           enclosed volume having the wrong sign.
#include "optimized/marching_cubes_vtk.h"

#include <stdexcept>

#include "core/marching_cubes.h"

#ifdef LOCKSTEP_HAVE_VTK

#include "optimized/peer_module.h"

namespace lockstep::opt::vtk {

bool available() { return !peer::find_module("vtk").empty(); }

// Recorded beside the module when it was built (cmake/peer_version.cpp), so
// that --version does not load VTK.
std::string version() {
  const std::string v = peer::recorded_version("vtk");
  return v.empty()
             ? "version not recorded (" + peer::module_file("vtk") + " has no .version beside it)"
             : v;
}

Mesh marching_cubes(const Volume& v, const FrameOptions& options, FrameStats* stats) {
  const mc::Settings s = mc::settings(options.params, v.source);
  Mesh m;
  if (v.cells() > 0) {
    const auto* api = static_cast<const ModuleApi*>(peer::open_api("vtk", kAbi));
    Request r;
    r.samples = v.data.data();
    r.nx = v.nx, r.ny = v.ny, r.nz = v.nz;
    r.spacing = v.spacing;
    r.origin = v.origin;
    r.iso = s.iso;
    r.threads = options.threads;
    api->marching_cubes(r, m);
  }
  if (stats) {
    stats->items = v.cells();
    if (m.triangles.empty())
      if (std::string note = mc::empty_note(v.data, s.iso); !note.empty())
        stats->notes.push_back(std::move(note));
  }
  return m;
}

}  // namespace lockstep::opt::vtk

#else  // no VTK: the row is not registered (registry/marching_cubes_row.cpp asks available()).

namespace lockstep::opt::vtk {

bool available() { return false; }
std::string version() { return {}; }
Mesh marching_cubes(const Volume&, const FrameOptions&, FrameStats*) {
  throw std::logic_error("lockstep was built without VTK: no vtk row");
}

}  // namespace lockstep::opt::vtk

#endif

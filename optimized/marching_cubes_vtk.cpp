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

#include <SMP/Common/vtkSMPToolsAPI.h>
#include <vtkCellArray.h>
#include <vtkDataArray.h>
#include <vtkFloatArray.h>
#include <vtkFlyingEdges3D.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkTypeInt32Array.h>
#include <vtkTypeInt64Array.h>
#include <vtkVersion.h>

#include <cstring>

namespace lockstep::opt::vtk {

namespace {

// vtkSMPTools.h does not compile as C++20 (GCC 12 rejects its constructors
// declared with a template-id, DR 2237), so this uses the object vtkSMPTools
// forwards to, as vtkSMPTools::LocalScope does: the thread count for one
// call, the previous one restored afterwards (it is process-wide state).
class SmpThreads {
 public:
  explicit SmpThreads(int threads) : old_(api().GetInternalDesiredNumberOfThread()) {
    api().Initialize(threads);
  }
  ~SmpThreads() { api().Initialize(old_); }
  SmpThreads(const SmpThreads&) = delete;
  SmpThreads& operator=(const SmpThreads&) = delete;
  static ::vtk::detail::smp::vtkSMPToolsAPI& api() {
    return ::vtk::detail::smp::vtkSMPToolsAPI::GetInstance();
  }

 private:
  int old_;
};

// VTK's connectivity (32- or 64-bit ids) as our triangles, orientation flipped.
template <class Array>
void copy_triangles(Array* conn, Mesh& m) {
  const vtkIdType n = conn->GetNumberOfValues() / 3;
  m.triangles.resize(size_t(n));
  const auto* p = conn->GetPointer(0);
  for (vtkIdType t = 0; t < n; ++t)
    m.triangles[size_t(t)] = {uint32_t(p[3 * t]), uint32_t(p[3 * t + 2]), uint32_t(p[3 * t + 1])};
}

}  // namespace

bool available() { return true; }

std::string version() {
  return std::string("VTK ") + vtkVersion::GetVTKVersion() + ", SMP backend " +
         SmpThreads::api().GetBackend();
}

Mesh marching_cubes(const Volume& v, const FrameOptions& options, FrameStats* stats) {
  const mc::Settings s = mc::settings(options.params, v.source);
  Mesh m;
  if (v.cells() > 0) {
    vtkNew<vtkFloatArray> scalars;
    scalars->SetNumberOfComponents(1);
    scalars->SetArray(const_cast<float*>(v.data.data()), vtkIdType(v.data.size()), 1);
    vtkNew<vtkImageData> image;
    image->SetDimensions(v.nx, v.ny, v.nz);
    image->SetSpacing(v.spacing.x, v.spacing.y, v.spacing.z);
    image->SetOrigin(v.origin.x, v.origin.y, v.origin.z);
    image->GetPointData()->SetScalars(scalars);

    vtkNew<vtkFlyingEdges3D> fe;
    fe->SetInputData(image);
    fe->SetNumberOfContours(1);
    fe->SetValue(0, s.iso);
    fe->ComputeNormalsOff();
    fe->ComputeGradientsOff();
    fe->ComputeScalarsOff();
    fe->InterpolateAttributesOff();
    {
      const SmpThreads scope(options.threads);
      fe->Update();
    }

    vtkPolyData* out = fe->GetOutput();
    if (vtkPoints* pts = out->GetPoints(); pts && pts->GetNumberOfPoints() > 0) {
      const vtkIdType np = pts->GetNumberOfPoints();
      m.vertices.resize(size_t(np));
      if (auto* f = vtkFloatArray::SafeDownCast(pts->GetData())) {
        static_assert(sizeof(Vec3f) == 3 * sizeof(float));
        std::memcpy(static_cast<void*>(m.vertices.data()), f->GetPointer(0),
                    size_t(np) * sizeof(Vec3f));
      } else {
        for (vtkIdType i = 0; i < np; ++i) {
          double p[3];
          pts->GetPoint(i, p);
          m.vertices[size_t(i)] = Vec3f(float(p[0]), float(p[1]), float(p[2]));
        }
      }
      vtkCellArray* polys = out->GetPolys();
      if (polys->GetNumberOfConnectivityIds() != 3 * polys->GetNumberOfCells())
        throw std::logic_error("vtkFlyingEdges3D returned polygons that are not triangles");
      if (polys->IsStorage64Bit())
        copy_triangles(polys->GetConnectivityArray64(), m);
      else
        copy_triangles(polys->GetConnectivityArray32(), m);
    }
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

#else  // no VTK: the row is not registered (pairs/marching_cubes.cpp asks available()).

namespace lockstep::opt::vtk {

bool available() { return false; }
std::string version() { return {}; }
Mesh marching_cubes(const Volume&, const FrameOptions&, FrameStats*) {
  throw std::logic_error("lockstep was built without VTK: no vtk row");
}

}  // namespace lockstep::opt::vtk

#endif

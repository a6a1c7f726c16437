// lockstep optimized: the vtk row's VTK calls, built as the module
// lockstep_peer_vtk.so (the only code linked against VTK; see
// optimized/peer_module.h and, for what is done and why, the top of
// optimized/marching_cubes_vtk.cpp, the host side). Nothing here calls into
// lockstep's libraries (linked with --no-undefined against VTK only).
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
#include <stdexcept>

#include "optimized/marching_cubes_vtk.h"

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

std::string version_string() {
  return std::string("VTK ") + vtkVersion::GetVTKVersion() + ", SMP backend " +
         SmpThreads::api().GetBackend();
}

void marching_cubes_into(const Request& v, Mesh& m) {
  m = Mesh{};
  {
    vtkNew<vtkFloatArray> scalars;
    scalars->SetNumberOfComponents(1);
    scalars->SetArray(const_cast<float*>(v.samples),
                      vtkIdType(size_t(v.nx) * size_t(v.ny) * size_t(v.nz)), 1);
    vtkNew<vtkImageData> image;
    image->SetDimensions(v.nx, v.ny, v.nz);
    image->SetSpacing(v.spacing.x, v.spacing.y, v.spacing.z);
    image->SetOrigin(v.origin.x, v.origin.y, v.origin.z);
    image->GetPointData()->SetScalars(scalars);

    vtkNew<vtkFlyingEdges3D> fe;
    fe->SetInputData(image);
    fe->SetNumberOfContours(1);
    fe->SetValue(0, v.iso);
    fe->ComputeNormalsOff();
    fe->ComputeGradientsOff();
    fe->ComputeScalarsOff();
    fe->InterpolateAttributesOff();
    {
      const SmpThreads scope(v.threads);
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
}

constexpr ModuleApi kApi = {kAbi, marching_cubes_into};

}  // namespace
}  // namespace lockstep::opt::vtk

extern "C" __attribute__((visibility("default"))) const void* lockstep_peer_api() {
  return &lockstep::opt::vtk::kApi;
}

// For cmake/peer_version.cpp at build time: the string --version prints.
extern "C" __attribute__((visibility("default"))) void lockstep_peer_version(char* out,
                                                                             unsigned long size) {
  const std::string v = lockstep::opt::vtk::version_string();
  if (size > 0) out[v.copy(out, size - 1)] = '\0';
}

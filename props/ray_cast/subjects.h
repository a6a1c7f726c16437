// lockstep props/ray_cast: the subjects, one per (typed row, implementation) of
// registry/ray_cast_row.h, every one answering in the same type.
//
// A subject answers, per ray of a Case, with a Hit: for a kernel (ray_sphere,
// ray_plane, ray_polygon, ray_cone) the case's own primitive (prim 0 on a hit), for a trace
// the whole scene (prim = the scene's primitive). Its oracle answers the same
// question with the same type (OracleTrace: per primitive, the nearest, the
// ties), so that every check is written once, for every subject.
//
// Which implementations are "textbook": the reference (first in each row) and
// every implementation whose name starts with the reference's (reference_f32).
// The decisions' unit roundoff is the row's Impl::decide_eps, or else inferred
// from the implementation's accuracy bound: bounds looser than 1e-9 mean float
// (2^-24), tighter mean double (2^-53).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "registry/ray_cast_row.h"
#include "props/ray_cast/case.h"
#include "props/ray_cast/oracle.h"

namespace lockstep::props::ray_cast {

enum class Mode { robust, textbook };

// What a subject computes with: it decides which generators fit it (never how a
// check judges it).
enum class Kernel { sphere, plane, polygon, frame, cone };

struct ImplInfo {
  std::string pair;  // the typed row's name
  std::string name;  // implementation name
  double bound = 0;  // Impl::accuracy
  double eps = 0;    // unit roundoff of the decisions
  Mode mode = Mode::robust;
  bool is_reference = false;
  double agree_t_rel = 0;  // Impl::agree (0 = the row's tolerance)
  // t refined in a wider type than the decisions (Impl::decide_eps set): t is
  // judged in the frame the refinement computes in (sphere: centre-relative;
  // polygon: the world plane equation), decisions with eps.
  bool refined = false;
  // Impl::known: this label is explained, never hidden, and its count per unit
  // of class known.per is capped at known.max_rate (props/driver/).
  KnownFailure known;
};

struct Subject {
  ImplInfo info;
  Kernel kernel = Kernel::sphere;
  KernelTolerance tol;  // the row's agreement tolerances
  // Per ray: the answer for the case's own primitive(s).
  std::function<std::vector<Hit>(const Case&)> answer;
  // The exact answer to the same question, per ray.
  std::function<OracleTrace(const Case&, const Ray&)> oracle;
  // Per ray: the nearest hit over every polygon of the scene (prim = the scene's
  // primitive); empty for subjects that cannot intersect polygons.
  std::function<std::vector<Hit>(const Case&)> answer_polygons;
  // Subjects that render a frame (empty: none).
  std::function<Image(const Scene&, const FrameOptions&, FrameStats*)> render;
  // Empty, or starts a run keeping its state across cases (registry/ray_cast_row.h
  // CasterFns::session: the embree row's device); with_session() uses it.
  CasterRun (*session)(RunResources& run) = nullptr;
};

// The subject on a session in run (its session's trace and render) when it
// has a session, else itself: the properties call this once per subject, so
// that a property binary makes one Embree device, the run's, not one per case.
Subject with_session(const Subject& s, RunResources& run);

// Every (row, implementation) of registry/ray_cast_row.h, the reference of each row first.
const std::vector<Subject>& all_subjects();
const Subject& reference_of(const std::string& pair);

}  // namespace lockstep::props::ray_cast

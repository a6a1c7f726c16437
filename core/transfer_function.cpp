// lockstep core: transfer functions (see core/transfer_function.h).
#include "core/transfer_function.h"

#include <algorithm>

namespace lockstep {

void TransferFunction::eval(double v, double out[4]) const {
  auto put = [out](const ControlPoint& p) {
    out[0] = p.r;
    out[1] = p.g;
    out[2] = p.b;
    out[3] = p.a;
  };
  if (v <= points.front().value) return put(points.front());
  if (v >= points.back().value) return put(points.back());
  // The first point above v, and the one before it.
  const auto hi = std::upper_bound(points.begin(), points.end(), v,
                                   [](double x, const ControlPoint& p) { return x < p.value; });
  const ControlPoint& a = hi[-1];
  const ControlPoint& b = *hi;
  const double t = (v - a.value) / (b.value - a.value);
  out[0] = a.r + t * (double(b.r) - a.r);
  out[1] = a.g + t * (double(b.g) - a.g);
  out[2] = a.b + t * (double(b.b) - a.b);
  out[3] = a.a + t * (double(b.a) - a.a);
}

double TransferFunction::max_alpha(double lo, double hi) const {
  double rgba[4];
  eval(lo, rgba);
  double m = rgba[3];
  eval(hi, rgba);
  m = std::max(m, rgba[3]);
  // Piecewise linear: the largest value inside is at a control point.
  for (const ControlPoint& p : points)
    if (p.value > lo && p.value < hi) m = std::max(m, double(p.a));
  return m;
}

const char* transfer_presets() { return "ct-bone|ct-skin|mri|ramp"; }

TransferFunction transfer_preset(const std::string& name) {
  TransferFunction tf;
  tf.source = name;
  // The CT head's numbers (histogram): air 0-100, soft tissue 900-1100, bone 1500-2300.
  if (name == "ct-bone")
    tf.points = {{0, 0, 0, 0, 0}, {1250, 0.90f, 0.85f, 0.75f, 0}, {1600, 0.95f, 0.90f, 0.80f, 0.4f},
                 {2200, 1, 0.97f, 0.92f, 0.9f}, {3272, 1, 1, 1, 0.95f}};
  else if (name == "ct-skin")
    tf.points = {{0, 0, 0, 0, 0},
                 {400, 0.90f, 0.60f, 0.50f, 0},
                 {700, 0.90f, 0.60f, 0.50f, 0.12f},
                 {950, 0.90f, 0.65f, 0.55f, 0},
                 {1250, 0.90f, 0.85f, 0.75f, 0},
                 {1600, 0.95f, 0.90f, 0.80f, 0.4f},
                 {2200, 1, 0.97f, 0.92f, 0.9f},
                 {3272, 1, 1, 1, 0.95f}};
  else if (name == "mri")
    tf.points = {{0, 0, 0, 0, 0}, {60, 0.8f, 0.6f, 0.5f, 0}, {90, 0.85f, 0.65f, 0.55f, 0.03f},
                 {130, 0.95f, 0.95f, 0.9f, 0.08f}, {255, 1, 1, 1, 0.3f}};
  else if (name == "ramp")
    tf.points = {{0, 1, 1, 1, 0}, {1, 1, 1, 1, 1}};
  return tf;
}

}  // namespace lockstep

// Phong shading of a packet of hits; see optimized/shade_simd.h.
#include "optimized/shade_simd.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/shading.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "optimized/shade_simd.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/contrib/math/math-inl.h"
#include "hwy/highway.h"

HWY_BEFORE_NAMESPACE();
namespace lockstep::opt {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

void ShadePacketImpl(const ShadeScene& s, ShadePacket& p) {
  const hn::CappedTag<float, ShadePacket::kLanes> df;
  const hn::RebindToSigned<decltype(df)> di;
  using VF = hn::Vec<decltype(df)>;
  const VF zero = hn::Zero(df), one = hn::Set(df, 1.0f), two = hn::Set(df, 2.0f);
  for (size_t k0 = 0; k0 < size_t(ShadePacket::kLanes); k0 += hn::Lanes(df)) {
    const VF px = hn::Load(df, p.px + k0), py = hn::Load(df, p.py + k0), pz = hn::Load(df, p.pz + k0);
    const VF nx = hn::Load(df, p.nx + k0), ny = hn::Load(df, p.ny + k0), nz = hn::Load(df, p.nz + k0);
    const VF vx = hn::Load(df, p.vx + k0), vy = hn::Load(df, p.vy + k0), vz = hn::Load(df, p.vz + k0);
    const VF kr = hn::Load(df, p.kr + k0), kg = hn::Load(df, p.kg + k0), kb = hn::Load(df, p.kb + k0);
    const VF ks = hn::Load(df, p.ks + k0), shine = hn::Load(df, p.shine + k0);
    // Ambient.
    const VF amb = hn::Set(df, float(kAmbient));
    VF r = hn::Mul(amb, kr), g = hn::Mul(amb, kg), b = hn::Mul(amb, kb);
    for (size_t l = 0; l < s.lx.size(); ++l) {
      // L: unit vector to the light.
      VF lx = hn::Sub(hn::Set(df, s.lx[l]), px);
      VF ly = hn::Sub(hn::Set(df, s.ly[l]), py);
      VF lz = hn::Sub(hn::Set(df, s.lz[l]), pz);
      const VF dist = hn::Sqrt(hn::MulAdd(lx, lx, hn::MulAdd(ly, ly, hn::Mul(lz, lz))));
      const VF inv = hn::Div(one, dist);
      lx = hn::Mul(lx, inv), ly = hn::Mul(ly, inv), lz = hn::Mul(lz, inv);
      const VF ndl = hn::MulAdd(nx, lx, hn::MulAdd(ny, ly, hn::Mul(nz, lz)));
      auto lit = hn::Gt(ndl, zero);  // light in front of the surface
      if (hn::AllFalse(df, lit)) continue;
      // What reaches the point of the light's intensity: attenuation times spot.
      VF reach = one;
      if (s.attenuated[l]) {
        // min(1, 1 / (c1 + c2 d + c3 d^2)); a zero denominator gives inf, clamped to 1.
        const VF den = hn::MulAdd(hn::MulAdd(hn::Set(df, s.c3[l]), dist, hn::Set(df, s.c2[l])), dist,
                                  hn::Set(df, s.c1[l]));
        reach = hn::Min(one, hn::Div(one, den));
      }
      if (s.spot[l]) {
        // cos of the angle between -L and D; outside the cone the light is off.
        const VF cos_a = hn::Neg(hn::MulAdd(lx, hn::Set(df, s.dx[l]),
                                            hn::MulAdd(ly, hn::Set(df, s.dy[l]), hn::Mul(lz, hn::Set(df, s.dz[l])))));
        lit = hn::And(lit, hn::Ge(cos_a, hn::Set(df, s.cos_cutoff[l])));
        if (hn::AllFalse(df, lit)) continue;
        if (s.exponent[l] != 0.0f) {  // exponent 0: a hard-edged cone, factor 1 inside
          // cos_a^exponent as exp(exponent log cos_a); cos_a <= 0 (only at a 90 degree cutoff) gives 0.
          const auto pos = hn::Gt(cos_a, zero);
          const VF safe = hn::IfThenElse(pos, cos_a, one);
          const VF falloff = hn::CallExp(df, hn::Mul(hn::Set(df, s.exponent[l]), hn::CallLog(df, safe)));
          reach = hn::Mul(reach, hn::IfThenElseZero(pos, falloff));
        }
      }
      // R = 2 (N.L) N - L, the mirror direction; specular = ks max(0, R.V)^shine.
      const VF rx = hn::MulSub(hn::Mul(two, ndl), nx, lx);
      const VF ry = hn::MulSub(hn::Mul(two, ndl), ny, ly);
      const VF rz = hn::MulSub(hn::Mul(two, ndl), nz, lz);
      const VF rdv = hn::MulAdd(rx, vx, hn::MulAdd(ry, vy, hn::Mul(rz, vz)));
      const auto shiny = hn::And(hn::Gt(rdv, zero), hn::Gt(ks, zero));
      VF spec = zero;
      if (!hn::AllFalse(df, shiny)) {
        const VF safe = hn::IfThenElse(shiny, rdv, hn::Set(df, 1.0f));
        spec = hn::IfThenElseZero(shiny, hn::Mul(ks, hn::CallExp(df, hn::Mul(shine, hn::CallLog(df, safe)))));
      }
      const VF d = hn::IfThenElseZero(lit, ndl);
      spec = hn::IfThenElseZero(lit, spec);
      r = hn::MulAdd(hn::Mul(reach, hn::Set(df, s.ir[l])), hn::MulAdd(d, kr, spec), r);
      g = hn::MulAdd(hn::Mul(reach, hn::Set(df, s.ig[l])), hn::MulAdd(d, kg, spec), g);
      b = hn::MulAdd(hn::Mul(reach, hn::Set(df, s.ib[l])), hn::MulAdd(d, kb, spec), b);
    }
    const auto hit = hn::RebindMask(df, hn::Ne(hn::Load(di, p.hit + k0), hn::Zero(di)));
    hn::Store(hn::IfThenElse(hit, r, hn::Set(df, float(s.background.x))), df, p.r + k0);
    hn::Store(hn::IfThenElse(hit, g, hn::Set(df, float(s.background.y))), df, p.g + k0);
    hn::Store(hn::IfThenElse(hit, b, hn::Set(df, float(s.background.z))), df, p.b + k0);
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace lockstep::opt
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace lockstep::opt {

HWY_EXPORT(ShadePacketImpl);

void shade_packet(const ShadeScene& s, ShadePacket& p) { HWY_DYNAMIC_DISPATCH(ShadePacketImpl)(s, p); }

ShadeScene prepare_shading(const Scene& scene, const simd::Frame& frame) {
  ShadeScene s;
  s.background = scene.background;
  const double default_ip = scene.lights.empty() ? 0.0 : 1.0 / std::sqrt(double(scene.lights.size()));
  for (const Light& l : scene.lights) {
    const Vec3 p = frame.point(l.position);
    s.lx.push_back(float(p.x)), s.ly.push_back(float(p.y)), s.lz.push_back(float(p.z));
    const Vec3 ip = l.has_color ? l.color : Vec3{default_ip, default_ip, default_ip};
    s.ir.push_back(float(ip.x)), s.ig.push_back(float(ip.y)), s.ib.push_back(float(ip.z));
    s.c1.push_back(float(l.atten.x)), s.c2.push_back(float(l.atten.y)), s.c3.push_back(float(l.atten.z));
    s.attenuated.push_back(l.atten != Vec3{1, 0, 0});
    const Vec3 dir = frame.dir(l.spot_dir);
    s.spot.push_back(l.spot);
    s.dx.push_back(float(dir.x)), s.dy.push_back(float(dir.y)), s.dz.push_back(float(dir.z));
    s.cos_cutoff.push_back(float(spot_cos_cutoff(l)));
    // Clamped to the float range: an overflowing exponent would give inf * log(1) = NaN.
    s.exponent.push_back(float(std::min(l.spot_exponent, double(std::numeric_limits<float>::max()))));
  }
  return s;
}

void fill_lane(const Scene& scene, const simd::Frame& frame, const Ray& ray, const Hit& hit, ShadePacket& p,
               int k) {
  p.hit[k] = hit.hit();
  if (!hit.hit()) {
    p.px[k] = p.py[k] = p.pz[k] = p.nx[k] = p.ny[k] = p.vx[k] = p.vy[k] = 0;
    p.nz[k] = p.vz[k] = 1;
    p.kr[k] = p.kg[k] = p.kb[k] = p.ks[k] = 0;
    p.shine[k] = 1;
    return;
  }
  // Hit point and normal in double (world), then into the frame.
  const Vec3& d = ray.d;  // unit length (render's primary rays)
  const Vec3 pw = ray.o + hit.t * ray.d;
  const Vec3 n = frame.dir(surface_normal(scene, hit.prim, hit.tri, pw, d));
  const Vec3 pf = frame.point(pw);
  const Vec3 v = frame.dir(-d);
  p.px[k] = float(pf.x), p.py[k] = float(pf.y), p.pz[k] = float(pf.z);
  p.nx[k] = float(n.x), p.ny[k] = float(n.y), p.nz[k] = float(n.z);
  p.vx[k] = float(v.x), p.vy[k] = float(v.y), p.vz[k] = float(v.z);
  const Material& m = scene.material_of_prim(hit.prim);
  p.kr[k] = float(m.kd * m.color.x), p.kg[k] = float(m.kd * m.color.y), p.kb[k] = float(m.kd * m.color.z);
  p.ks[k] = float(m.ks);
  p.shine[k] = float(m.shine);
}

}  // namespace lockstep::opt
#endif  // HWY_ONCE

// lockstep props/volume: the volume-rendering families' properties (volume,
// volume_iso, splat; registry/volume_rows.cpp lists the parts each runs).
//
// A case is a small volume drawn by RapidCheck -- 4 to 40 samples per axis,
// random anisotropic spacing and origin; smooth fields (a few Gaussian blobs),
// rough ones (independent samples) or analytic ones (io/volume_io.h's
// sample_field: sphere, torus, gyroid, Marschner-Lobb, then stretched per axis)
// -- a transfer function of 2 to 8 control points over the field's range (the
// points below a random cut transparent, as ct-bone's, and a quarter of the
// others: so that macro cells are skipped), a view (azimuth,
// elevation, roll; a quarter with image rows along x), a step, eps, an iso value and a frame of 4 to 32 pixels a
// side. Its text form has every number as a hexfloat, so a counterexample
// replays bit for bit. The transfer function reaches the renderer as a .tf
// file written to the temporary directory (named by the hash of its text).
//
//   Agreement.<family>__<impl>   (part "agreement") the implementation's image
//       against the reference's at the same settings: every pixel's largest
//       channel difference within the family's tolerance (Family::tol.abs,
//       measured in float against double, registry/volume_rows.cpp: volume 6e-4 for a
//       measured 3.7e-4; volume_iso measured 0, the same image; splat 5e-5
//       for a measured 2.25e-5: the reference's footprints from tables, in
//       float). Failures print the case (seed, volume, settings) and each
//       pixel over: both outputs and the error. A pixel may
//       differ by up to eps where both rays stopped at the 1 - eps threshold:
//       float and double can cross it one sample apart (label
//       termination_flip, explained; both alphas at least 1 - eps - 1e-5, the
//       difference at most eps + tol; measured 1 to 4 pixels in 1.6M; splat:
//       a pixel stops taking footprints one splat apart, 13 in 3.3M).
//   SkipChangesNothing.volume__<impl>  (part "skip") noskip against skip: every
//       channel within 1e-6 (a skipped sample has alpha' exactly 0: measured 0);
//       and eps = 0 (never stop) against the case's eps > 0: every channel
//       within eps + 1e-5 (what stopping leaves out is at most (1 - A) <= eps).
//   TransparentGivesBackground.<family>__<impl>  (part "transparent") a transfer
//       function whose alphas are all 0: every pixel exactly (0, 0, 0, 0).
//   Mirror.<family>__<impl>      (part "mirror") the volume flipped along x
//       (sample i <-> nx - 1 - i, the same box), seen from azimuth 180 - az and
//       roll -roll: the image mirrored left-right, every channel within
//       kMirrorTol (the rays are the mirror images of each other up to the
//       rounding of their origins; termination flips as in Agreement). Splat
//       too: footprints of equal depth form one sheet, composited at once
//       (before: in index order, which the flip reverses; 1.3% of pixels
//       differed, up to 0.1, looking straight down the z axis).
#include <functional>
#include <string>

#include "props/property.h"
#include "props/volume/case.h"
#include "props/volume/checks.h"
#include "props/volume/generators.h"

namespace lockstep::props::volume {

namespace {

Property property(const Family& family, const FamilyImpl& impl, std::string suite, std::string check,
                  std::string generator, rc::Gen<VrCase> gen, double bound,
                  std::function<Verdict(const VrCase&)> judge) {
  Property p = case_property<VrCase>(family, impl, std::move(suite), std::move(check), std::move(generator),
                                     "largest channel difference", "pixels", std::move(gen), std::move(judge),
                                     write_case, read_case);
  p.bound = bound;
  return p;
}

}  // namespace

FamilyProperties properties(const Family& family, RunResources&) {
  FamilyProperties out;
  const FamilyImpl& ref = family.reference();
  const Family* fam = &family;
  for (const FamilyImpl& impl : family.impls) {
    const FamilyImpl* ip = &impl;
    // A peer of another resampling (volpack: shear-warp, 8 bits, classified
    // then interpolated) is held to its own measured agreement on chosen frames
    // (tests/volpack_test.cpp: within its bound, wrong views caught) and in the
    // corpus, not to these float-against-double bounds; on random volumes dense
    // at the box's faces its soft edge alone puts 9-42% of pixels over 32/255.
    // It still must give the background for a transparent transfer function.
    const bool own_method = !impl.agree;
    if (family.has_property("agreement") && &impl != &ref && own_method)
      out.properties.push_back(property(family, impl, "Agreement", "agreement", "volumes", gen_case(false),
                                        family.tol.abs, [fam, &ref, ip](const VrCase& c) {
                                          return agreement(*fam, ref, *ip, c);
                                        }));
    if (family.has_property("skip") && &impl != &ref && own_method)
      out.properties.push_back(property(family, impl, "SkipChangesNothing", "skip", "volumes_empty_space",
                                        gen_case(false, true), 1e-6,
                                        [fam, ip](const VrCase& c) { return skip_changes_nothing(*fam, *ip, c); }));
    if (family.has_property("transparent"))
      out.properties.push_back(property(family, impl, "TransparentGivesBackground", "transparent",
                                        "volumes_transparent_tf", gen_case(true), 0,
                                        [fam, ip](const VrCase& c) { return transparent(*fam, *ip, c); }));
    if (family.has_property("mirror") && own_method)
      out.properties.push_back(property(family, impl, "Mirror", "mirror", "volumes", gen_case(false), kMirrorTol,
                                        [fam, ip](const VrCase& c) { return mirror(*fam, *ip, c); }));
  }
  return out;
}

}  // namespace lockstep::props::volume

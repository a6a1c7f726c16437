// lockstep verify: one case of any family, through its output kind
// (core/output.h), which writes, reads, compares and draws the outputs.
//
//   1. the reference against its golden golden/<case><kind's extension>
//      (written by the reference only, --regolden): every sample within
//      kGoldenTolerance;
//   2. every other implementation the case lists against the reference at the
//      case's thresholds (default: the family's tolerance), and never a sample
//      off by more than the family's hard limit or NaN, whatever the budget;
//   3. with an analytic judge (the family's, e.g. ray_cast's disk and convex),
//      every implementation, the reference included, against the closed form:
//      the optimized ones must match it; the reference must do what the
//      manifest expects (ref=right / ref=wrong), and a run where it does not
//      fails. On the samples both show, outputs are compared with the
//      reference too.
// A case's `beside` picture (another renderer's image of the scene) is put in
// its report folder by the kind (save_beside), scaled to the frame's size;
// never judged.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "app/run.h"
#include "app/verify.h"

namespace lockstep::cli {

namespace fs = std::filesystem;

std::vector<Row> verify_case(const Case& c, const VerifyOptions& o, std::vector<std::string>& verdicts,
                             RowSessions& sessions) {
  const Family& fam = *c.family;
  const OutputKind& kind = *fam.kind;
  const FamilyImpl& ref = fam.reference();
  const int w = c.frame_width(), h = c.frame_height();
  FrameOptions opts;
  opts.width = w;
  opts.height = h;
  opts.threads = o.threads;
  opts.params = c.params;
  std::vector<Row> rows;
  const fs::path case_dir = o.report_dir / c.name;
  std::error_code ec;
  if (!o.no_report) {
    fs::create_directories(case_dir, ec);
    if (ec) throw InputError(case_dir.string(), 0, "cannot create the report folder: " + ec.message());
  }
  // Report files, relative to the report folder ("" without a report).
  auto view = [&](const Output& out, const std::string& stem) -> std::string {
    if (o.no_report) return {};
    return c.name + "/" + fs::path(kind.save_view(out, (case_dir / stem).string())).filename().string();
  };
  auto difference = [&](const Output& a, const Output& b, const Tolerance& tol, const std::string& stem) -> std::string {
    if (o.no_report) return {};
    return c.name + "/" + fs::path(kind.save_difference(a, b, tol, (case_dir / stem).string())).filename().string();
  };
  const std::string golden_path = (o.golden_dir / (c.name + std::string(kind.golden_extension))).string();
  // The golden is the same code on the same input: every sample within kGoldenTolerance.
  Tolerance golden_tol;
  golden_tol.abs = kGoldenTolerance;
  golden_tol.fraction = 1;
  golden_tol.hard = kInfinity;

  // 1. The reference, against its golden (or making it).
  const Run r_ref = run_frame(fam, ref, c.input, opts, true, sessions.of(ref, c.input, opts));
  Row rr;
  rr.case_name = c.name;
  rr.family = std::string(fam.name);
  rr.impl = std::string(ref.name);
  rr.ran = r_ref.ok;
  rr.seconds = r_ref.seconds;
  rr.items = r_ref.stats.items;
  rr.speedup = 1.0;
  rr.dropped = r_ref.stats.dropped_count();
  rr.dropped_why = r_ref.stats.dropped_text();
  if (!r_ref.ok) {
    rr.note = r_ref.error;
  } else if (o.regolden) {
    kind.write_golden(r_ref.out, golden_path);
    Tolerance readback = golden_tol;
    readback.abs = kGoldenTolerance / 4;
    if (!kind.compare(r_ref.out, kind.read(golden_path), readback).pass)
      throw InputError(golden_path, 0, "the golden does not read back within " + fmt("%g", kGoldenTolerance / 4) +
                                           " (values too large for its format?)");
    rr.pass = true;
    rr.note = "golden written: " + golden_path;
    std::printf("%-22s %dx%d  %.3f s  -> %s\n", c.name.c_str(), w, h, r_ref.seconds, golden_path.c_str());
    rows.push_back(rr);
    return rows;
  } else if (!fs::exists(golden_path)) {
    rr.note = "no golden " + golden_path + " (make it with scripts/regolden.sh)";
  } else {
    const Output golden = kind.read(golden_path);
    rr.err = kind.compare(golden, r_ref.out, golden_tol);
    rr.pass = rr.err.pass;
    rr.note = !rr.err.comparable ? "golden has another size"
              : rr.pass          ? "= golden (within " + fmt("%g", kGoldenTolerance) + ")"
                                 : "differs from golden (tolerance " + fmt("%g", kGoldenTolerance) + ")";
    if (rr.err.comparable) rr.difference = difference(golden, r_ref.out, golden_tol, "reference-heat");
    rr.golden = view(golden, "golden");
  }
  if (r_ref.ok) rr.view = view(r_ref.out, "reference");
  if (!o.no_report && !c.beside.empty()) kind.save_beside(c.beside, w, h, (case_dir / kBesideStem).string());
  if (rr.dropped != 0) rr.note += (rr.note.empty() ? "" : "; ") + rr.dropped_why;

  // The analytic judge, if any: the reference must do what the manifest expects.
  JudgeFrame judge;
  std::string verdict;
  if (c.judge) {
    judge = c.judge->prepare(c.input, opts);
    verdict = c.name + ": ";
    if (r_ref.ok) {
      const JudgeVerdict j = judge(r_ref.out, nullptr, c.tol);
      if (!j.picture.empty()) rr.judged = view(j.picture, "reference-judge");
      std::string what;
      bool unexpected = false;
      if (j.wrong > 0) {
        what = "reference WRONG" + (c.ref_reason.empty() ? "" : " (" + c.ref_reason + ")") + ": " + j.detail;
        unexpected = c.ref_expect == RefExpect::kRight;
        if (unexpected) what += " UNEXPECTED: the manifest says ref=right";
        else if (c.ref_expect == RefExpect::kWrong) what += ", as expected";
      } else {
        what = "reference right: matches analytic (" + j.detail + ")";
        unexpected = c.ref_expect == RefExpect::kWrong;
        if (unexpected)
          what += " UNEXPECTED: the manifest says ref=wrong" + (c.ref_reason.empty() ? "" : ":" + c.ref_reason);
      }
      if (unexpected) rr.pass = false;
      rr.note += "; " + what;
      verdict += what;
    } else {
      verdict += "reference did not run";
    }
  }
  print_row(rr);
  rows.push_back(rr);

  // 2. Every other implementation, against the reference (and the judge).
  for (const FamilyImpl& impl : fam.impls) {
    const std::string name(impl.name);
    if (&impl == &ref) continue;
    if (!c.impls.empty() && std::find(c.impls.begin(), c.impls.end(), name) == c.impls.end()) continue;
    if (!o.only.empty() && std::find(o.only.begin(), o.only.end(), name) == o.only.end()) continue;
    // A peer that cannot draw this case's settings is not run (no row), and says why.
    if (impl.unsupported) {
      const std::string why = impl.unsupported(opts.params);
      if (!why.empty()) {
        std::printf("%-22s %-10s n/a: %s\n", c.name.c_str(), name.c_str(), why.c_str());
        continue;
      }
    }
    const Run r = run_frame(fam, impl, c.input, opts, true, sessions.of(impl, c.input, opts));
    // The row's own agreement (FamilyImpl::agree) unless the manifest's line sets one.
    const Tolerance& tol = c.tol_given ? c.tol : impl.tolerance(c.tol);
    Row row;
    row.case_name = c.name;
    row.family = std::string(fam.name);
    row.impl = name;
    row.ran = r.ok;
    row.seconds = r.seconds;
    row.items = r.stats.items;
    row.speedup = r.seconds > 0 ? r_ref.seconds / r.seconds : 0;
    if (!r.ok) {
      row.note = r.error;
      if (judge) verdict += "; " + name + " " + r.error;
    } else {
      row.view = view(r.out, name);
      if (r_ref.ok) {
        row.err = kind.compare(r_ref.out, r.out, tol);
        row.difference = difference(r_ref.out, r.out, tol, name + "-heat");
      }
      if (!judge) {
        row.pass = r_ref.ok && row.err.pass;
        if (!r_ref.ok) row.note = "no reference to compare with";
        else if (!row.err.pass) row.note = "differs from reference: " + kind.describe(row.err, tol);
      } else {
        const JudgeVerdict j = judge(r.out, r_ref.ok ? &r_ref.out : nullptr, tol);
        if (!j.picture.empty()) row.judged = view(j.picture, name + "-judge");
        row.pass = j.wrong == 0;
        row.note = row.pass ? "analytic: right (" + j.detail + ")" : "analytic: WRONG, " + j.detail;
        if (r_ref.ok) {
          // Where both show something, the output must agree with the reference.
          const Agreement& b = j.with_reference;
          const long allowed = long(std::floor((1.0 - tol.fraction) * double(b.samples) + 1e-9));
          // A reference expected wrong (cancellation moves its t, so its shading)
          // is no yardstick: then the comparison is only reported.
          const bool enforced = c.ref_expect != RefExpect::kWrong;
          if (enforced) row.pass = row.pass && b.pass;
          row.note += "; colour vs reference on " + std::to_string(b.samples) + " " + std::string(kind.sample) +
                      " both cover: " + std::to_string(b.over) + " over " + fmt("%.4g", tol.abs) +
                      (b.pass ? "" : enforced ? " (FAIL, " + std::to_string(allowed) + " allowed)"
                                              : " (not enforced: the reference is expected wrong)");
        }
        verdict += "; " + name + (row.pass ? " right" : " WRONG (" + std::to_string(j.wrong) + " " + std::string(kind.sample) + ")");
      }
    }
    if (!r.stats.chosen.empty()) row.note += (row.note.empty() ? "" : "; ") + std::string("chose ") + r.stats.chosen;
    row.dropped = r.stats.dropped_count();
    row.dropped_why = r.stats.dropped_text();
    if (row.dropped != 0) row.note += (row.note.empty() ? "" : "; ") + row.dropped_why;
    print_row(row);
    rows.push_back(row);
  }
  if (judge) {
    std::printf("  => %s\n", verdict.c_str());
    verdicts.push_back(verdict);
  }
  return rows;
}

}  // namespace lockstep::cli

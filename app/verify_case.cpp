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
//
// verify_case runs the steps of a CaseCheck in that order: the report folder,
// the reference's row (run; its golden; its pictures; its judge), then each
// other implementation's row.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "app/run.h"
#include "app/verify.h"

namespace lockstep::cli {

namespace fs = std::filesystem;

namespace {

// The golden is the same code on the same input: every sample within kGoldenTolerance.
Tolerance golden_tolerance() {
  Tolerance t;
  t.abs = kGoldenTolerance;
  t.fraction = 1;
  t.hard = kInfinity;
  return t;
}

// more after a row's note, "; " between.
void add_note(std::string& note, const std::string& more) {
  note += (note.empty() ? "" : "; ") + more;
}

// What every row says of its run: whose, whether it ran, its time and work,
// what it dropped.
Row row_of(const Case& c, const FamilyImpl& impl, const Run& r) {
  Row row;
  row.case_name = c.name;
  row.family = std::string(c.family->name);
  row.impl = std::string(impl.name);
  row.ran = r.ok;
  row.seconds = r.seconds;
  row.items = r.stats.items;
  row.dropped = r.stats.dropped_count();
  row.dropped_why = r.stats.dropped_text();
  return row;
}

// The analytic judge's verdict j on the reference against what the manifest
// expects of it (ref=right / ref=wrong), in words; unexpected: they disagree.
std::string reference_verdict(const Case& c, const JudgeVerdict& j, bool& unexpected) {
  std::string what;
  if (j.wrong > 0) {
    what = "reference WRONG" + (c.ref_reason.empty() ? "" : " (" + c.ref_reason + ")") + ": " +
           j.detail;
    unexpected = c.ref_expect == RefExpect::kRight;
    if (unexpected)
      what += " UNEXPECTED: the manifest says ref=right";
    else if (c.ref_expect == RefExpect::kWrong)
      what += ", as expected";
  } else {
    what = "reference right: matches analytic (" + j.detail + ")";
    unexpected = c.ref_expect == RefExpect::kWrong;
    if (unexpected)
      what += " UNEXPECTED: the manifest says ref=wrong" +
              (c.ref_reason.empty() ? "" : ":" + c.ref_reason);
  }
  return what;
}

// One case's verification, step by step (the file's header).
class CaseCheck {
 public:
  // Makes the case's report folder (unless there is no report).
  CaseCheck(const Case& c, const VerifyOptions& o, RowSessions& sessions)
      : c_(c), o_(o), sessions_(sessions), kind_(*c.family->kind), ref_(c.family->reference()) {
    opts_.width = c.frame_width();
    opts_.height = c.frame_height();
    opts_.threads = o.threads;
    opts_.params = c.params;
    case_dir_ = o.report_dir / c.name;
    golden_path_ = (o.golden_dir / (c.name + std::string(kind_.golden_extension))).string();
    if (o.no_report) return;
    std::error_code ec;
    fs::create_directories(case_dir_, ec);
    if (ec)
      throw InputError(case_dir_.string(), 0, "cannot create the report folder: " + ec.message());
  }

  const FamilyImpl& reference() const { return ref_; }
  bool judged() const { return bool(judge_); }
  // The analytic judge's line for the run: the reference, then each row.
  const std::string& verdict() const { return verdict_; }

  Run run(const FamilyImpl& impl) {
    return run_frame(*c_.family, impl, c_.input, opts_, true, sessions_.of(impl, c_.input, opts_));
  }

  // --regolden: the reference's output r_ref (which ran) becomes the golden,
  // which must read back; its row is the case's only one.
  Row write_golden(const Run& r_ref) const {
    Row rr = row_of(c_, ref_, r_ref);
    rr.speedup = 1.0;
    kind_.write_golden(r_ref.out, golden_path_);
    Tolerance readback = golden_tolerance();
    readback.abs = kGoldenTolerance / 4;
    if (!kind_.compare(r_ref.out, kind_.read(golden_path_), readback).pass)
      throw InputError(golden_path_, 0,
                       "the golden does not read back within " + fmt("%g", kGoldenTolerance / 4) +
                           " (values too large for its format?)");
    rr.pass = true;
    rr.note = "golden written: " + golden_path_;
    std::printf("%-22s %dx%d  %.3f s  -> %s\n", c_.name.c_str(), opts_.width, opts_.height,
                r_ref.seconds, golden_path_.c_str());
    return rr;
  }

  // 1. The reference's row: against its golden, its pictures, the case's
  // beside picture, and the analytic judge (which then judges every row).
  Row reference_row(const Run& r_ref) {
    Row rr = row_of(c_, ref_, r_ref);
    rr.speedup = 1.0;
    if (!r_ref.ok)
      rr.note = r_ref.error;
    else
      against_golden(rr, r_ref);
    if (r_ref.ok) rr.view = view(r_ref.out, "reference");
    if (!o_.no_report && !c_.beside.empty())
      kind_.save_beside(c_.beside, opts_.width, opts_.height, (case_dir_ / kBesideStem).string());
    if (rr.dropped != 0) add_note(rr.note, rr.dropped_why);
    if (c_.judge) judge_reference(rr, r_ref);
    return rr;
  }

  // Whether impl gets a row: not the reference, listed by the case and --impl,
  // and able to draw the case's settings (else a line says why not).
  bool takes_part(const FamilyImpl& impl) const {
    const std::string name(impl.name);
    if (&impl == &ref_) return false;
    if (!c_.impls.empty() && std::find(c_.impls.begin(), c_.impls.end(), name) == c_.impls.end())
      return false;
    if (!o_.only.empty() && std::find(o_.only.begin(), o_.only.end(), name) == o_.only.end())
      return false;
    if (impl.unsupported) {
      const std::string why = impl.unsupported(opts_.params);
      if (!why.empty()) {
        std::printf("%-22s %-10s n/a: %s\n", c_.name.c_str(), name.c_str(), why.c_str());
        return false;
      }
    }
    return true;
  }

  // 2. Another implementation's row: run, against the reference (and the judge).
  Row row(const FamilyImpl& impl, const Run& r_ref) {
    const std::string name(impl.name);
    const Run r = run(impl);
    // The row's own agreement (FamilyImpl::agree) unless the manifest's line sets one.
    const Tolerance& tol = c_.tol_given ? c_.tol : impl.tolerance(c_.tol);
    Row row = row_of(c_, impl, r);
    row.speedup = r.seconds > 0 ? r_ref.seconds / r.seconds : 0;
    if (!r.ok) {
      row.note = r.error;
      if (judge_) verdict_ += "; " + name + " " + r.error;
    } else {
      row.view = view(r.out, name);
      if (r_ref.ok) {
        row.err = kind_.compare(r_ref.out, r.out, tol);
        row.difference = difference(r_ref.out, r.out, tol, name + "-heat");
      }
      if (!judge_) {
        row.pass = r_ref.ok && row.err.pass;
        if (!r_ref.ok)
          row.note = "no reference to compare with";
        else if (!row.err.pass)
          row.note = "differs from reference: " + kind_.describe(row.err, tol);
      } else {
        judge_row(row, r, r_ref, tol);
      }
    }
    if (!r.stats.chosen.empty()) add_note(row.note, std::string("chose ") + r.stats.chosen);
    if (row.dropped != 0) add_note(row.note, row.dropped_why);
    return row;
  }

 private:
  // Report files, relative to the report folder ("" without a report).
  std::string view(const Output& out, const std::string& stem) const {
    if (o_.no_report) return {};
    return report_file(kind_.save_view(out, (case_dir_ / stem).string()));
  }
  std::string difference(const Output& a, const Output& b, const Tolerance& tol,
                         const std::string& stem) const {
    if (o_.no_report) return {};
    return report_file(kind_.save_difference(a, b, tol, (case_dir_ / stem).string()));
  }
  std::string report_file(const std::string& path) const {
    return c_.name + "/" + fs::path(path).filename().string();
  }

  // The reference's output (it ran) against its golden, if there is one.
  void against_golden(Row& rr, const Run& r_ref) const {
    if (!fs::exists(golden_path_)) {
      rr.note = "no golden " + golden_path_ + " (make it with scripts/regolden.sh)";
      return;
    }
    const Tolerance golden_tol = golden_tolerance();
    const Output golden = kind_.read(golden_path_);
    rr.err = kind_.compare(golden, r_ref.out, golden_tol);
    rr.pass = rr.err.pass;
    rr.note = !rr.err.comparable ? "golden has another size"
              : rr.pass          ? "= golden (within " + fmt("%g", kGoldenTolerance) + ")"
                        : "differs from golden (tolerance " + fmt("%g", kGoldenTolerance) + ")";
    if (rr.err.comparable)
      rr.difference = difference(golden, r_ref.out, golden_tol, "reference-heat");
    rr.golden = view(golden, "golden");
  }

  // The analytic judge, prepared for the case's frame: the reference must do
  // what the manifest expects.
  void judge_reference(Row& rr, const Run& r_ref) {
    judge_ = c_.judge->prepare(c_.input, opts_);
    verdict_ = c_.name + ": ";
    if (!r_ref.ok) {
      verdict_ += "reference did not run";
      return;
    }
    const JudgeVerdict j = judge_(r_ref.out, nullptr, c_.tol);
    if (!j.picture.empty()) rr.judged = view(j.picture, "reference-judge");
    bool unexpected = false;
    const std::string what = reference_verdict(c_, j, unexpected);
    if (unexpected) rr.pass = false;
    rr.note += "; " + what;
    verdict_ += what;
  }

  // The judge's verdict on a row's output r (which ran), and where both show
  // something, its agreement with the reference's.
  void judge_row(Row& row, const Run& r, const Run& r_ref, const Tolerance& tol) {
    const JudgeVerdict j = judge_(r.out, r_ref.ok ? &r_ref.out : nullptr, tol);
    if (!j.picture.empty()) row.judged = view(j.picture, row.impl + "-judge");
    row.pass = j.wrong == 0;
    row.note = row.pass ? "analytic: right (" + j.detail + ")" : "analytic: WRONG, " + j.detail;
    if (r_ref.ok) {
      // Where both show something, the output must agree with the reference.
      const Agreement& b = j.with_reference;
      const long allowed = long(std::floor((1.0 - tol.fraction) * double(b.samples) + 1e-9));
      // A reference expected wrong (cancellation moves its t, so its shading)
      // is no yardstick: then the comparison is only reported.
      const bool enforced = c_.ref_expect != RefExpect::kWrong;
      if (enforced) row.pass = row.pass && b.pass;
      row.note += "; colour vs reference on " + std::to_string(b.samples) + " " +
                  std::string(kind_.sample) + " both cover: " + std::to_string(b.over) + " over " +
                  fmt("%.4g", tol.abs) +
                  (b.pass     ? ""
                   : enforced ? " (FAIL, " + std::to_string(allowed) + " allowed)"
                              : " (not enforced: the reference is expected wrong)");
    }
    verdict_ +=
        "; " + row.impl +
        (row.pass ? " right"
                  : " WRONG (" + std::to_string(j.wrong) + " " + std::string(kind_.sample) + ")");
  }

  const Case& c_;
  const VerifyOptions& o_;
  RowSessions& sessions_;
  const OutputKind& kind_;
  const FamilyImpl& ref_;
  FrameOptions opts_;
  fs::path case_dir_;        // the case's report folder
  std::string golden_path_;  // the reference's golden
  JudgeFrame judge_;         // the analytic judge for the frame (empty: none)
  std::string verdict_;      // its line
};

}  // namespace

std::vector<Row> verify_case(const Case& c, const VerifyOptions& o,
                             std::vector<std::string>& verdicts, RowSessions& sessions) {
  CaseCheck check(c, o, sessions);
  const Run r_ref = check.run(check.reference());
  if (r_ref.ok && o.regolden) return {check.write_golden(r_ref)};
  std::vector<Row> rows;
  auto add = [&](Row row) {
    print_row(row);
    rows.push_back(std::move(row));
  };
  add(check.reference_row(r_ref));
  for (const FamilyImpl& impl : c.family->impls)
    if (check.takes_part(impl)) add(check.row(impl, r_ref));
  if (check.judged()) {
    std::printf("  => %s\n", check.verdict().c_str());
    verdicts.push_back(check.verdict());
  }
  return rows;
}

}  // namespace lockstep::cli

// lockstep verify: the rows for CI dashboards -- JUnit XML and JSON.
//
// JUnit (--junit FILE): the format Jenkins, GitLab, GitHub Actions' test
// reporters and Buildkite read: <testsuites> with one <testsuite> per family
// and one <testcase> per (case, implementation) row, classname
// "lockstep.<family>", name "<case>.<impl>", time in seconds (fixed point,
// as junit-10.xsd wants: tests/schemas/junit-10.xsd); a failing row
// carries <failure message="..."> with the row's note, its error figures and
// the report's pictures (paths relative to the report folder).
//
// JSON (--json FILE), schema "lockstep-verify/1":
//   { "schema": "lockstep-verify/1", "cases": N, "rows": [ROW...], "pass": bool }
//   ROW = { "case", "family", "impl": string, "ran", "pass": bool,
//           "samples", "over", "over_hard": integer (samples compared, over the
//             tolerance, over the hard limit; 0 samples: not compared),
//           "worst", "score": number or null (null: infinite, e.g. identical),
//           "seconds", "speedup": number, "note", "detail": string,
//           "view", "difference", "judged": string (report files, "" when none),
//           "dropped": integer (primitives the row could not draw, FrameStats::dropped),
//           "dropped_why": string (per reason, "2 dropped (why); ..."; "" when none) }
// Both are written whole to FILE.tmp and renamed: never half a file.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

#include "app/verify.h"

namespace lockstep::cli {

namespace fs = std::filesystem;

std::string json_string(const std::string& s) {
  std::string o = "\"";
  for (const unsigned char ch : s) {
    switch (ch) {
      case '"': o += "\\\""; break;
      case '\\': o += "\\\\"; break;
      case '\n': o += "\\n"; break;
      case '\t': o += "\\t"; break;
      default:
        if (ch < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", ch);
          o += buf;
        } else {
          o += char(ch);
        }
    }
  }
  return o + "\"";
}

std::string json_number(double x) {
  if (!std::isfinite(x)) return "null";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", x);
  return buf;
}

namespace {

std::string xml(const std::string& s) {
  std::string o;
  for (const unsigned char ch : s) {
    switch (ch) {
      case '&': o += "&amp;"; break;
      case '<': o += "&lt;"; break;
      case '>': o += "&gt;"; break;
      case '"': o += "&quot;"; break;
      default:
        // XML 1.0 allows no other control characters than tab, newline, return.
        if (ch < 0x20 && ch != '\t' && ch != '\n' && ch != '\r') o += ' ';
        else o += char(ch);
    }
  }
  return o;
}

// JUnit times: fixed-point seconds, never an exponent (junit-10.xsd's
// Surefire pattern, which suites and the root are held to, allows none).
std::string junit_time(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6f", std::isfinite(x) && x > 0 ? x : 0.0);
  return buf;
}

std::string failure_text(const Row& r) {
  std::ostringstream m;
  m << (r.note.empty() ? std::string(r.ran ? "differs" : "did not run") : r.note);
  if (r.err.samples > 0)
    m << " (worst " << json_number(r.err.worst) << ", " << r.err.over << " of " << r.err.samples << " over)";
  return m.str();
}

}  // namespace

void write_whole(const fs::path& path, const std::string& text) {
  const fs::path tmp = path.string() + ".tmp";
  {
    std::ofstream f(tmp, std::ios::binary);
    f << text;
    if (!f.flush()) {
      std::error_code ec;
      fs::remove(tmp, ec);
      throw InputError(path.string(), 0, "cannot write");
    }
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw InputError(path.string(), 0, "cannot write: " + ec.message());
  }
}

std::string row_json(const Row& r) {
  std::ostringstream s;
  s << "{\"case\": " << json_string(r.case_name) << ", \"family\": " << json_string(r.family)
    << ", \"impl\": " << json_string(r.impl) << ", \"ran\": " << (r.ran ? "true" : "false")
    << ", \"pass\": " << (r.pass ? "true" : "false") << ", \"samples\": " << r.err.samples
    << ", \"over\": " << r.err.over << ", \"over_hard\": " << r.err.over_hard
    << ", \"worst\": " << json_number(r.err.worst) << ", \"score\": " << json_number(r.err.score)
    << ", \"seconds\": " << json_number(r.seconds) << ", \"speedup\": " << json_number(r.speedup)
    << ", \"note\": " << json_string(r.note) << ", \"detail\": " << json_string(r.err.detail)
    << ", \"view\": " << json_string(r.view) << ", \"difference\": " << json_string(r.difference)
    << ", \"judged\": " << json_string(r.judged) << ", \"dropped\": " << r.dropped
    << ", \"dropped_why\": " << json_string(r.dropped_why) << "}";
  return s.str();
}

void write_json(const fs::path& path, size_t cases, const std::vector<Row>& rows) {
  std::ostringstream s;
  bool all = true;
  for (const Row& r : rows) all = all && r.pass;
  s << "{\n  \"schema\": \"lockstep-verify/1\",\n  \"cases\": " << cases << ",\n  \"pass\": "
    << (all ? "true" : "false") << ",\n  \"rows\": [";
  for (size_t i = 0; i < rows.size(); ++i) {
    s << (i ? ",\n" : "\n") << "    " << row_json(rows[i]);
  }
  s << "\n  ]\n}\n";
  write_whole(path, s.str());
}

void write_junit(const fs::path& path, const std::vector<Row>& rows) {
  // One suite per family, in the order families first appear.
  std::vector<std::string> families;
  std::map<std::string, std::vector<const Row*>> by_family;
  for (const Row& r : rows) {
    if (!by_family.count(r.family)) families.push_back(r.family);
    by_family[r.family].push_back(&r);
  }
  long failures = 0;
  double total = 0;
  for (const Row& r : rows) {
    failures += r.pass ? 0 : 1;
    total += r.seconds;
  }
  std::ostringstream s;
  s << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  s << "<testsuites name=\"lockstep verify\" tests=\"" << rows.size() << "\" failures=\"" << failures
    << "\" errors=\"0\" time=\"" << junit_time(total) << "\">\n";
  for (const std::string& fam : families) {
    const auto& rs = by_family[fam];
    long f = 0;
    double t = 0;
    for (const Row* r : rs) {
      f += r->pass ? 0 : 1;
      t += r->seconds;
    }
    s << "  <testsuite name=\"lockstep." << xml(fam) << "\" tests=\"" << rs.size() << "\" failures=\"" << f
      << "\" errors=\"0\" skipped=\"0\" time=\"" << junit_time(t) << "\">\n";
    for (const Row* r : rs) {
      s << "    <testcase classname=\"lockstep." << xml(fam) << "\" name=\"" << xml(r->case_name + "." + r->impl)
        << "\" time=\"" << junit_time(r->seconds) << "\"";
      if (r->pass) {
        s << "/>\n";
        continue;
      }
      s << ">\n      <failure message=\"" << xml(failure_text(*r)) << "\" type=\"" << (r->ran ? "differs" : "error")
        << "\">" << xml(failure_text(*r));
      for (const std::string* file : {&r->view, &r->difference, &r->judged})
        if (!file->empty()) s << "\nreport file: " << xml(*file);
      s << "</failure>\n    </testcase>\n";
    }
    s << "  </testsuite>\n";
  }
  s << "</testsuites>\n";
  write_whole(path, s.str());
}

}  // namespace lockstep::cli

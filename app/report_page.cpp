// lockstep verify --report DIR: the page people look at, DIR/index.html.
//
// The page is app/report_page.h's template with the run's data put in; the data
// are also written alone as DIR/report.json so that `lockstep merge-reports`
// can rebuild the page of several shards from their data (app/merge_reports.cpp).
//
// DIR/report.json, schema "lockstep-report/1":
//   { "schema": "lockstep-report/1", "lockstep": version string,
//     "threads": integer (0: unknown), "cases": N, "pass": bool,
//     "rows": [ROW...]            the rows exactly as lockstep-verify/1's
//                                 (app/verify_export.cpp),
//     "case_info": [CASE...],     one per case, in run order,
//     "verdicts": [string...],    the analytic judges' verdict lines,
//     "merged_from": integer      (merged pages only: how many reports) }
//   CASE = { "case", "family", "kind" (the output kind: "image", "mesh"),
//            "legend" (what the kind's pictures show), "input" (file name),
//            "size" (WxH rendered, or what the reference produced in the kind's
//            samples, "2256 vertices"; "" when unknown), "tolerance" (in words), "judge",
//            "golden" (the golden's picture, relative to DIR; "" when none): string,
//            "work": integer (what the reference run did, in "unit": FrameStats::items; 0 when
//            not counted), "unit": the family's unit ("rays", "triangles", "pixels", "cubes"),
//            "beside", "beside_from": another renderer's picture of the scene (the case's
//            folder's beside picture, written by the kind's save_beside, and the corpus
//            file it was scaled from), never judged; present only for cases that have one }
//
// DIR/<case>/pixels.js: lockstepPixels("<case>", {"<case>/<file>.png": "data:image/png;base64,...",
// ...}) with every picture of the case folder (the files with the kind's picture_extension, as
// data: URIs of its picture_type), for the page's pixel readout (images read from file://
// taint a canvas; data: URIs loaded by a script do not).
#include "app/report_page.h"

#include <algorithm>
#include <fstream>
#include <sstream>
#include <thread>

#include "app/verify.h"

namespace lockstep::cli {

namespace fs = std::filesystem;

namespace {

std::string base64(const std::string& bytes) {
  static constexpr char kDigits[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = (unsigned char)bytes[i] << 16 | (unsigned char)bytes[i + 1] << 8 |
                       (unsigned char)bytes[i + 2];
    out += {kDigits[v >> 18], kDigits[v >> 12 & 63], kDigits[v >> 6 & 63], kDigits[v & 63]};
  }
  if (i + 1 == bytes.size()) {
    const unsigned v = (unsigned char)bytes[i] << 16;
    out += {kDigits[v >> 18], kDigits[v >> 12 & 63], '=', '='};
  } else if (i + 2 == bytes.size()) {
    const unsigned v = (unsigned char)bytes[i] << 16 | (unsigned char)bytes[i + 1] << 8;
    out += {kDigits[v >> 18], kDigits[v >> 12 & 63], kDigits[v >> 6 & 63], '='};
  }
  return out;
}

std::string read_bytes(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  if (!f) throw InputError(p.string(), 0, "cannot read");
  return s.str();
}

// The case folder's pictures as data: URIs (a file per case, loaded when the case is opened).
void write_pixels(const fs::path& dir, const Case& c) {
  const OutputKind& k = *c.family->kind;
  const fs::path case_dir = dir / c.name;
  std::vector<fs::path> pictures;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(case_dir, ec))
    if (e.path().extension() == k.picture_extension) pictures.push_back(e.path());
  std::sort(pictures.begin(), pictures.end());
  const std::string uri = "data:" + std::string(k.picture_type) + ";base64,";
  std::string js = "lockstepPixels(" + json_string(c.name) + ", {";
  for (size_t i = 0; i < pictures.size(); ++i)
    js += (i ? ",\n  " : "\n  ") + json_string(c.name + "/" + pictures[i].filename().string()) +
          ": \"" + uri + base64(read_bytes(pictures[i])) + "\"";
  js += "\n});\n";
  write_whole(case_dir / "pixels.js", js);
}

}  // namespace

std::string report_data(const std::vector<Case>& cases, const std::vector<Row>& rows,
                        const std::vector<std::string>& verdicts, int threads) {
  bool all = true;
  for (const Row& r : rows) all = all && r.pass;
  std::ostringstream s;
  s << "{\n  \"schema\": \"lockstep-report/1\",\n  \"lockstep\": " << json_string(LOCKSTEP_VERSION)
    << ",\n  \"threads\": " << (threads > 0 ? threads : int(std::thread::hardware_concurrency()))
    << ",\n  \"cases\": " << cases.size() << ",\n  \"pass\": " << (all ? "true" : "false")
    << ",\n  \"rows\": [";
  for (size_t i = 0; i < rows.size(); ++i) s << (i ? ",\n    " : "\n    ") << row_json(rows[i]);
  s << "\n  ],\n  \"case_info\": [";
  for (size_t i = 0; i < cases.size(); ++i) {
    const Case& c = cases[i];
    const OutputKind& k = *c.family->kind;
    std::string golden;
    uint64_t work = 0;
    // Sized families (images) render at WxH; the others' size is what the
    // reference produced, in the kind's samples ("2256 vertices").
    std::string size =
        c.family->sized ? std::to_string(c.frame_width()) + "x" + std::to_string(c.frame_height())
                        : "";
    for (const Row& r : rows) {
      if (r.case_name != c.name) continue;
      if (!r.golden.empty()) golden = r.golden;
      if (r.impl == c.family->reference().name) work = r.items;
      if (!c.family->sized && r.impl == c.family->reference().name && r.err.samples > 0)
        size = std::to_string(r.err.samples) + " " + std::string(k.samples);
    }
    s << (i ? ",\n    " : "\n    ") << "{\"case\": " << json_string(c.name)
      << ", \"family\": " << json_string(std::string(c.family->name))
      << ", \"kind\": " << json_string(std::string(k.name))
      << ", \"legend\": " << json_string(std::string(k.legend))
      << ", \"input\": " << json_string(fs::path(c.input_path).filename().string())
      << ", \"size\": " << json_string(size)
      << ", \"tolerance\": " << json_string(k.describe_tolerance(c.tol)) << ", \"judge\": "
      << json_string(c.judge ? std::string(c.judge->name) : std::string("reference"))
      << ", \"golden\": " << json_string(golden) << ", \"work\": " << work
      << ", \"unit\": " << json_string(std::string(c.family->unit));
    if (!c.beside.empty())
      s << ", \"beside\": " << json_string(c.name + "/" + beside_file(c))
        << ", \"beside_from\": " << json_string(c.beside_name);
    s << "}";
  }
  s << "\n  ],\n  \"verdicts\": [";
  for (size_t i = 0; i < verdicts.size(); ++i)
    s << (i ? ",\n    " : "\n    ") << json_string(verdicts[i]);
  s << "\n  ]\n}\n";
  return s.str();
}

void write_page(const fs::path& dir, const std::string& data, const std::vector<Case>& cases) {
  for (const Case& c : cases) write_pixels(dir, c);
  // Inside <script>, "</" could end the block: JSON allows "<\/" for it.
  std::string safe;
  safe.reserve(data.size());
  for (size_t i = 0; i < data.size(); ++i) {
    safe += data[i];
    if (data[i] == '<' && i + 1 < data.size() && data[i + 1] == '/') safe += '\\';
  }
  const std::string_view marker = "@LOCKSTEP_DATA@";
  const size_t at = kReportPage.find(marker);
  std::string page(kReportPage.substr(0, at));
  page += safe;
  page += kReportPage.substr(at + marker.size());
  write_whole(dir / "report.json", data);
  write_whole(dir / "index.html", page);
}

}  // namespace lockstep::cli

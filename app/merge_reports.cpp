// lockstep merge-reports OUT_DIR REPORT_DIR...: the shards of a run, one report.
//
// A CI matrix runs `lockstep verify --shard K/N --report shard-K` on N machines;
// each REPORT_DIR is one such folder (its report.json, lockstep-report/1,
// app/report_page.cpp, and its case folders). merge-reports reads every
// report.json first -- a missing or malformed one, or a (case, impl) row or a
// case in two of them, is an error naming the file(s), exit 2, and nothing is
// written -- then builds OUT_DIR beside it as OUT_DIR.partial (the case folders
// copied, report.json, index.html, verify.json as --json writes it, verify.xml
// as --junit writes it) and renames it to OUT_DIR, replacing an OUT_DIR that
// is a report folder (has report.json) or empty. An input FILE.json is a
// shard's `verify --json` file (lockstep-verify/1): its rows join without
// pictures (the merged rows name none), its cases with nothing but their family.
#include <cstdio>
#include <map>
#include <set>
#include <sstream>

#include "app/json_read.h"
#include "app/verify.h"

namespace lockstep::cli {

namespace fs = std::filesystem;

namespace {

void print_help() {
  std::printf(
      "usage: lockstep merge-reports OUT_DIR REPORT_DIR|FILE.json...\n"
      "\n"
      "Joins the reports of a sharded run into one: each REPORT_DIR is the --report folder\n"
      "of one `lockstep verify --shard K/N --report REPORT_DIR` (any number, any order).\n"
      "Writes OUT_DIR/index.html (the page, as verify writes it, over every shard's rows),\n"
      "OUT_DIR/report.json (its data, lockstep-report/1), OUT_DIR/verify.json (the rows as\n"
      "--json writes them, lockstep-verify/1), OUT_DIR/verify.xml (as --junit writes them),\n"
      "and copies each shard's case folders (pictures) into OUT_DIR. An input ending in .json\n"
      "is a shard's `verify --json FILE` (lockstep-verify/1, e.g. from --no-report runs): its\n"
      "rows are merged without pictures (their picture paths are dropped).\n"
      "\n"
      "Every REPORT_DIR/report.json is read and checked before anything is written; OUT_DIR\n"
      "is built as OUT_DIR.partial and renamed into place, replacing an earlier report there.\n"
      "\n"
      "A CI matrix of four machines:\n"
      "  lockstep verify --shard K/4 --report shard-K     (K = 0..3, one per machine)\n"
      "  lockstep merge-reports report shard-0 shard-1 shard-2 shard-3\n"
      "\n"
      "Exit codes: 0 merged and every row passes, 1 merged and some row fails, 2 bad usage,\n"
      "a missing or malformed report.json, the same (case, impl) row or case in two reports,\n"
      "or OUT_DIR cannot be written.\n");
}

struct Shard {
  std::string file;  // REPORT_DIR/report.json, or the --json file itself
  fs::path dir;
  JsonValue doc;
  bool rows_only = false;  // a --json file (lockstep-verify/1): rows, no pictures
};

const JsonValue& member(const JsonValue& obj, const std::string& key, JsonValue::Type type,
                        const std::string& file, const std::string& where) {
  static const char* kNames[] = {"null",     "a boolean", "a number",
                                 "a string", "an array",  "an object"};
  const JsonValue* v = obj.find(key);
  if (!v) throw InputError(file, obj.line, where + ": no \"" + key + "\"");
  if (v->type != type && !(type == JsonValue::Type::kNumber && v->type == JsonValue::Type::kNull))
    throw InputError(file, v->line, where + ": \"" + key + "\" is not " + kNames[int(type)]);
  return *v;
}

// A number; null (written for infinite values) reads back as infinity.
double number(const JsonValue& obj, const std::string& key, const std::string& file,
              const std::string& where) {
  const JsonValue& v = member(obj, key, JsonValue::Type::kNumber, file, where);
  return v.type == JsonValue::Type::kNull ? kInfinity : v.number;
}

long count(const JsonValue& obj, const std::string& key, const std::string& file,
           const std::string& where) {
  const JsonValue& v = member(obj, key, JsonValue::Type::kNumber, file, where);
  if (v.type == JsonValue::Type::kNull || !v.integer || v.number < 0)
    throw InputError(file, v.line, where + ": \"" + key + "\" is not a count");
  return long(v.number);
}

Row row_of(const JsonValue& o, const std::string& file, const std::string& where) {
  using T = JsonValue::Type;
  if (o.type != T::kObject) throw InputError(file, o.line, where + ": not an object");
  auto str = [&](const char* k) { return member(o, k, T::kString, file, where).string; };
  auto boolean = [&](const char* k) { return member(o, k, T::kBool, file, where).boolean; };
  Row r;
  r.case_name = str("case");
  r.family = str("family");
  r.impl = str("impl");
  if (r.case_name.empty() || r.family.empty() || r.impl.empty())
    throw InputError(file, o.line, where + ": empty case, family or impl");
  r.ran = boolean("ran");
  r.pass = boolean("pass");
  r.err.samples = count(o, "samples", file, where);
  r.err.over = count(o, "over", file, where);
  r.err.over_hard = count(o, "over_hard", file, where);
  r.err.worst = number(o, "worst", file, where);
  r.err.score = number(o, "score", file, where);
  r.seconds = number(o, "seconds", file, where);
  r.speedup = number(o, "speedup", file, where);
  r.note = str("note");
  r.err.detail = str("detail");
  r.view = str("view");
  r.difference = str("difference");
  r.judged = str("judged");
  r.dropped = uint64_t(count(o, "dropped", file, where));
  r.dropped_why = str("dropped_why");
  return r;
}

}  // namespace

int merge_reports_main(Args args) {
  std::vector<std::string> dirs;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string_view a = args[i];
    if (a == "--help" || a == "-h") {
      print_help();
      return kExitOk;
    }
    if (is_option(a)) unknown_option(a);
    dirs.emplace_back(a);
  }
  if (dirs.size() < 2) throw UsageError("needs OUT_DIR and at least one REPORT_DIR");
  const fs::path out = fs::path(dirs.front()).lexically_normal();
  dirs.erase(dirs.begin());

  // 1. Read and check everything; nothing is written before this holds.
  std::vector<Shard> shards;
  for (const std::string& d : dirs) {
    Shard s;
    s.dir = d;
    s.rows_only = fs::path(d).extension() == ".json";
    s.file = s.rows_only ? d : (fs::path(d) / "report.json").string();
    std::error_code ec;
    if (fs::equivalent(fs::path(d), out, ec))
      throw UsageError("OUT_DIR '" + out.string() + "' is also an input report");
    s.doc = read_json_file(s.file);
    if (s.doc.type != JsonValue::Type::kObject)
      throw InputError(s.file, s.doc.line, "not a JSON object");
    const JsonValue* schema = s.doc.find("schema");
    const std::string want = s.rows_only ? "lockstep-verify/1" : "lockstep-report/1";
    if (!schema || schema->type != JsonValue::Type::kString || schema->string != want)
      throw InputError(
          s.file, schema ? schema->line : 1,
          std::string(s.rows_only ? "not a verify --json file" : "not a lockstep report") +
              " (schema is not \"" + want + "\")");
    shards.push_back(std::move(s));
  }
  using T = JsonValue::Type;
  std::vector<Row> rows;
  std::vector<std::string> case_info, verdicts, case_names;
  std::map<std::pair<std::string, std::string>, std::string> row_from;  // (case, impl) -> its file
  std::map<std::string, std::string> case_from;
  long cases = 0;
  for (const Shard& s : shards) {
    cases += count(s.doc, "cases", s.file, "report");
    const JsonValue& rs = member(s.doc, "rows", T::kArray, s.file, "report");
    for (size_t k = 0; k < rs.array.size(); ++k) {
      Row r = row_of(rs.array[k], s.file, "rows[" + std::to_string(k) + "]");
      // A --json file brings no pictures: its rows name none in the merged report.
      if (s.rows_only) r.view = r.difference = r.judged = "";
      const auto key = std::make_pair(r.case_name, r.impl);
      if (auto it = row_from.find(key); it != row_from.end())
        throw InputError(s.file, rs.array[k].line,
                         "row (" + r.case_name + ", " + r.impl + ") is in " + it->second +
                             " too: a shard merged twice?");
      row_from[key] = s.file;
      rows.push_back(std::move(r));
    }
    if (s.rows_only) {
      // Its cases, as the rows name them, with nothing else known.
      for (size_t k = 0; k < rs.array.size(); ++k) {
        const Row& r = rows[rows.size() - rs.array.size() + k];
        if (case_from.count(r.case_name)) {
          if (case_from[r.case_name] == s.file) continue;
          throw InputError(s.file, rs.array[k].line,
                           "case " + r.case_name + " is in " + case_from[r.case_name] + " too");
        }
        case_from[r.case_name] = s.file;
        case_names.push_back(r.case_name);
        case_info.push_back("{\"case\": " + json_string(r.case_name) +
                            ", \"family\": " + json_string(r.family) +
                            ", \"kind\": \"?\", \"legend\": \"\", \"input\": \"\", \"size\": \"\", "
                            "\"tolerance\": \"\", \"judge\": \"?\", \"golden\": \"\"}");
      }
      continue;
    }
    const JsonValue& ci = member(s.doc, "case_info", T::kArray, s.file, "report");
    for (size_t k = 0; k < ci.array.size(); ++k) {
      const std::string where = "case_info[" + std::to_string(k) + "]";
      if (ci.array[k].type != T::kObject)
        throw InputError(s.file, ci.array[k].line, where + ": not an object");
      const std::string name = member(ci.array[k], "case", T::kString, s.file, where).string;
      if (name.empty() || name.find('/') != std::string::npos ||
          name.find("..") != std::string::npos)
        throw InputError(s.file, ci.array[k].line, where + ": bad case name '" + name + "'");
      if (auto it = case_from.find(name); it != case_from.end())
        throw InputError(s.file, ci.array[k].line,
                         "case " + name + " is in " + it->second + " too");
      case_from[name] = s.file;
      case_names.push_back(name);
      case_info.push_back(to_json(ci.array[k]));
      if (!fs::is_directory(s.dir / name))
        throw InputError((s.dir / name).string(), 0,
                         "the case folder is missing (report.json names it)");
    }
    for (const JsonValue& v : member(s.doc, "verdicts", T::kArray, s.file, "report").array) {
      if (v.type != T::kString) throw InputError(s.file, v.line, "verdicts: not a string");
      verdicts.push_back(v.string);
    }
  }
  for (const Row& r : rows)
    if (!case_from.count(r.case_name))
      throw InputError(row_from[{r.case_name, r.impl}], 0,
                       "row of case " + r.case_name + " has no case_info");

  // 2. Build OUT_DIR.partial, then rename it into place.
  std::error_code ec;
  if (fs::exists(out) && !fs::exists(out / "report.json") && !fs::is_empty(out, ec))
    throw InputError(out.string(), 0,
                     "exists and is not a report folder (no report.json): not replacing it");
  const fs::path partial = out.string() + ".partial";
  fs::remove_all(partial, ec);
  fs::create_directories(partial, ec);
  if (ec) throw InputError(partial.string(), 0, "cannot create: " + ec.message());
  try {
    for (const Shard& s : shards) {
      if (s.rows_only) continue;  // no pictures to copy
      for (const JsonValue& ci : s.doc.find("case_info")->array) {
        const std::string name = ci.find("case")->string;
        fs::copy(s.dir / name, partial / name, fs::copy_options::recursive, ec);
        if (ec)
          throw InputError((s.dir / name).string(), 0,
                           "cannot copy to " + (partial / name).string() + ": " + ec.message());
      }
    }
    bool all = true;
    for (const Row& r : rows) all = all && r.pass;
    const JsonValue* version = shards.front().doc.find("lockstep");
    const JsonValue* threads = shards.front().doc.find("threads");
    std::ostringstream d;
    d << "{\n  \"schema\": \"lockstep-report/1\",\n  \"lockstep\": "
      << json_string(version && version->type == T::kString ? version->string
                                                            : std::string(LOCKSTEP_VERSION))
      << ",\n  \"threads\": "
      << (threads && threads->type == T::kNumber ? long(threads->number) : 0)
      << ",\n  \"cases\": " << cases << ",\n  \"pass\": " << (all ? "true" : "false")
      << ",\n  \"merged_from\": " << shards.size() << ",\n  \"rows\": [";
    for (size_t i = 0; i < rows.size(); ++i) d << (i ? ",\n    " : "\n    ") << row_json(rows[i]);
    d << "\n  ],\n  \"case_info\": [";
    for (size_t i = 0; i < case_info.size(); ++i) d << (i ? ",\n    " : "\n    ") << case_info[i];
    d << "\n  ],\n  \"verdicts\": [";
    for (size_t i = 0; i < verdicts.size(); ++i)
      d << (i ? ",\n    " : "\n    ") << json_string(verdicts[i]);
    d << "\n  ]\n}\n";
    // The shards' pixels.js came with their case folders.
    write_page(partial, d.str(), {});
    write_json(partial / "verify.json", size_t(cases), rows);
    write_junit(partial / "verify.xml", rows);
    if (fs::exists(out)) fs::remove_all(out, ec);
    if (ec) throw InputError(out.string(), 0, "cannot replace: " + ec.message());
    fs::rename(partial, out, ec);
    if (ec)
      throw InputError(out.string(), 0,
                       "cannot rename " + partial.string() + " to it: " + ec.message());
    long failed = 0;
    for (const Row& r : rows) failed += r.pass ? 0 : 1;
    std::printf("%ld cases, %zu rows from %zu reports: %s\n", cases, rows.size(), shards.size(),
                all ? "all PASS" : (std::to_string(failed) + " FAIL").c_str());
    std::fprintf(stderr, "lockstep merge-reports: %s, verify.json and verify.xml in %s\n",
                 (out / "index.html").string().c_str(), out.string().c_str());
    return all ? kExitOk : kExitFail;
  } catch (...) {
    fs::remove_all(partial, ec);
    throw;
  }
}

}  // namespace lockstep::cli

// lockstep verify: reading corpus/manifest.txt (its format: the comment at its top).
#include <cctype>

#include "app/verify.h"
#include "io/tokenizer.h"
#include "registry/loaders.h"
#include "spd/spd.h"

namespace lockstep::cli {

namespace fs = std::filesystem;

namespace {

std::vector<std::string> split(std::string_view s, char sep) {
  std::vector<std::string> out;
  size_t i = 0;
  while (i <= s.size()) {
    size_t j = s.find(sep, i);
    if (j == std::string_view::npos) j = s.size();
    if (j > i) out.emplace_back(s.substr(i, j - i));
    i = j + 1;
  }
  return out;
}

}  // namespace

std::vector<Case> read_manifest(const fs::path& dir) {
  const std::string path = (dir / "manifest.txt").string();
  const char* cannot = fs::is_directory(dir) ? "cannot open the manifest" : "no such corpus folder";
  const std::string text = text::read_text_file(
      path,
      {.missing = cannot,
       .folder = "cannot read the manifest",
       .unreadable = cannot,
       .read_error = "cannot read the manifest"},
      text::kMaxListBytes);
  std::vector<Case> cases;
  text::Tokenizer in(text, path, {.comments = text::Comments::anywhere});
  while (in.next()) {
    const int line_no = in.line_no();
    std::vector<std::string> w(in.words().begin(), in.words().end());
    auto fail = [&](const std::string& what) -> void { in.fail(what); };
    Case c;
    c.line = line_no;
    // The optional family column: a line starting with a family's name.
    c.family = registry().find(w[0]);
    if (c.family) w.erase(w.begin());
    else c.family = &registry().families.front();
    const Family& fam = *c.family;
    // The family's settings: name=value fields anywhere after the family (not ref=).
    for (auto it = w.begin(); it != w.end();) {
      const size_t eq = it->find('=');
      if (eq == std::string::npos || eq == 0 || it->starts_with("ref=")) {
        ++it;
        continue;
      }
      if (it->starts_with("beside=")) {
        c.beside_name = it->substr(7);
        c.beside = (dir / c.beside_name).string();
        if (c.beside_name.empty() || !fs::is_regular_file(c.beside)) fail("beside: no such picture '" + c.beside + "'");
        it = w.erase(it);
        continue;
      }
      // '@PATH': a file of the corpus (a transfer function), relative to this folder.
      const std::string value = it->substr(eq + 1);
      c.params.set(it->substr(0, eq), value.starts_with('@') ? (dir / value.substr(1)).string() : value);
      it = w.erase(it);
    }
    if (!c.params.items.empty()) {
      if (!fam.check_params) fail(std::string(fam.name) + " takes no settings, got '" + c.params.str() + "'");
      try {
        fam.check_params(c.params);
      } catch (const InputError& e) {
        fail(e.what());
      }
    }
    if (w.size() < 2 || w.size() > 8)
      fail("expected '[family] case input [size [impls [fail [failpercent [judge [ref]]]]]]', got " +
           std::to_string(w.size()) + " fields after the family");
    c.name = w[0];
    for (char ch : c.name)
      if (!(std::isalnum(static_cast<unsigned char>(ch)) || ch == '-' || ch == '_' || ch == '.'))
        fail("case name '" + c.name + "' may only use letters, digits, '-', '_' and '.'");
    for (const Case& other : cases)
      if (other.name == c.name) fail("case '" + c.name + "' given twice (first on line " + std::to_string(other.line) + ")");
    // 'spd:NAME' (e.g. spd:gears-4): an SPD scene, read from ../shared/spd or
    // generated (`lockstep spd`), for NFF families.
    c.input_path = w[1].starts_with("spd:") ? w[1] : (dir / w[1]).string();
    if (w[1].starts_with("spd:") && !fam.reads(".nff"))
      fail("'" + w[1] + "': SPD scenes are NFF; " + std::string(fam.name) + " does not read NFF");
    if (w[1].starts_with("spd:") && !spd::parse_stem(w[1].substr(4)))
      fail("'" + w[1] + "': not an SPD scene name (NAME-SIZE[-tess]; see lockstep spd --help)");
    c.tol = fam.tol;
    auto given = [&](size_t i) { return w.size() > i && w[i] != "-"; };
    try {
      if (given(2)) {
        if (!fam.sized) fail(std::string(fam.name) + " takes its size from the input: size must be '-'");
        parse_size(w[2], c.width, c.height);
      }
      if (given(3) && w[3] == "none") {
        // The reference alone (against its golden): no implementation is named
        // "none", so the filter in app/verify_case.cpp runs no other row.
        c.impls = {"none"};
      } else if (given(3)) {
        c.impls = split(w[3], ',');
        for (const std::string& n : c.impls) {
          (void)find_impl(fam, n);
          if (n == fam.reference().name) fail("impls: the reference is always run; list the others");
        }
      }
      if (given(4)) c.tol.abs = parse_number("fail", w[4], 0, 1e30);
      if (given(5)) c.tol.fraction = 1.0 - parse_number("failpercent", w[5], 0, 100) / 100.0;
      c.tol_given = given(4) || given(5);
    } catch (const UsageError& e) {
      fail(e.what());
    }
    if (given(6) && w[6] != "reference") {
      c.judge = fam.find_judge(w[6]);
      if (!c.judge) {
        std::string known = "reference";
        for (const auto& j : fam.judges) known += ", " + std::string(j.name);
        fail("judge of " + std::string(fam.name) + " must be one of " + known + ", got '" + w[6] + "'");
      }
    }
    if (given(7)) {
      if (!c.judge) fail("a 'ref=' expectation needs an analytic judge");
      const std::string& r = w[7];
      if (r == "ref=right") {
        c.ref_expect = RefExpect::kRight;
      } else if (r.starts_with("ref=wrong")) {
        c.ref_expect = RefExpect::kWrong;
        if (r.size() > 9) {
          if (r[9] != ':') fail("expected 'ref=right', 'ref=wrong' or 'ref=wrong:REASON', got '" + r + "'");
          c.ref_reason = r.substr(10);
        }
      } else {
        fail("expected 'ref=right', 'ref=wrong' or 'ref=wrong:REASON', got '" + r + "'");
      }
    }
    cases.push_back(std::move(c));
  }
  if (cases.empty()) throw InputError(path, 0, "no cases in the manifest");
  return cases;
}

void load_inputs(std::vector<Case>& cases) {
  for (Case& c : cases) {
    if (c.input_path.starts_with("spd:")) {
      std::optional<Input> in = load_spd(std::string_view(c.input_path).substr(4));
      if (!in) throw InputError(c.input_path, 0, "not an SPD scene name (NAME-SIZE[-tess]; see lockstep spd --help)");
      c.input = std::move(*in);
    } else {
      c.input = c.family->load(c.input_path);
    }
    if (c.family->sized && (c.frame_width() <= 0 || c.frame_height() <= 0))
      throw InputError(c.input_path, 0, "no size: give one in the manifest");
    if (c.judge) c.judge->check(c.input);
  }
}

}  // namespace lockstep::cli

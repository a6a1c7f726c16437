// lockstep verify: splitting the cases over machines (see app/verify.h).
//
// CI systems run a matrix of jobs on separate machines and tell each which
// part it is; GoogleTest's protocol (GTEST_TOTAL_SHARDS, GTEST_SHARD_INDEX,
// GTEST_SHARD_STATUS_FILE) is what test runners already set, so verify reads
// it as the property binary does. The split is by case (a case's rows share
// its input and reference run), balanced by each case's measured cost
// (corpus/costs.txt, written by scripts/case_costs.py from a `verify --json`
// run): longest-processing-time-first, deterministic.
#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <map>

#include "app/verify.h"
#include "io/text.h"
#include "io/tokenizer.h"

namespace lockstep::cli {

namespace fs = std::filesystem;

std::vector<std::pair<std::string, double>> read_costs(const fs::path& corpus_dir) {
  std::vector<std::pair<std::string, double>> out;
  const fs::path path = corpus_dir / "costs.txt";
  if (!std::ifstream(path)) return out;
  const std::string text = text::read_text_file(path.string(), {}, text::kMaxListBytes);
  text::Tokenizer in(text, path.string(), {.comments = text::Comments::anywhere});
  while (in.next()) {
    const auto& w = in.words();
    double s = -1;
    if (w.size() != 2 || !text::parse_double(w[1], s) || !(s >= 0 && s < 1e6))
      in.fail("expected 'case seconds', got '" + std::string(in.line()) + "'");
    out.emplace_back(std::string(w[0]), s);
  }
  return out;
}

std::vector<Case> shard_of(std::vector<Case> cases, const std::vector<std::pair<std::string, double>>& costs, int k,
                           int n) {
  std::map<std::string, double> cost(costs.begin(), costs.end());
  std::vector<double> known;
  for (const auto& [name, s] : costs) known.push_back(s);
  std::sort(known.begin(), known.end());
  const double fallback = known.empty() ? 1.0 : known[known.size() / 2];
  // Costliest first; equal costs in name order (the manifest's order may differ
  // between checkouts only if the manifest does: names are the key).
  std::vector<size_t> order(cases.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  auto cost_of = [&](size_t i) {
    const auto it = cost.find(cases[i].name);
    return it == cost.end() ? fallback : it->second;
  };
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    const double ca = cost_of(a), cb = cost_of(b);
    return ca != cb ? ca > cb : cases[a].name < cases[b].name;
  });
  std::vector<double> load(size_t(n), 0.0);
  std::vector<int> shard_of_case(cases.size());
  for (const size_t i : order) {
    const size_t least = size_t(std::min_element(load.begin(), load.end()) - load.begin());
    shard_of_case[i] = int(least);
    load[least] += cost_of(i);
  }
  std::vector<Case> mine;
  for (size_t i = 0; i < cases.size(); ++i)
    if (shard_of_case[i] == k) mine.push_back(std::move(cases[i]));
  return mine;
}

void shard_from_environment(int& k, int& n) {
  const char* total = std::getenv("GTEST_TOTAL_SHARDS");
  const char* index = std::getenv("GTEST_SHARD_INDEX");
  if (!total || !index || !*total || !*index) return;
  n = int(parse_long("GTEST_TOTAL_SHARDS", total, 1, 100000));
  k = int(parse_long("GTEST_SHARD_INDEX", index, 0, n - 1));
  if (const char* status = std::getenv("GTEST_SHARD_STATUS_FILE"); status && *status) std::ofstream(status).flush();
}

}  // namespace lockstep::cli

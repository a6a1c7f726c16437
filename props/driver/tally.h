// lockstep props/driver: what the driver counts per property, and where it writes it.
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "props/verdict.h"

namespace lockstep::props::driver {

std::string g3(double x);  // "%.3g"

// The most known failures a run may show: the largest count k with
// P(X >= k) >= 1e-6 for X ~ Binomial(n, max_rate), i.e. more than this is
// evidence (at 1e-6) that the true rate is over max_rate.
long known_failure_cap(long n, double max_rate);
// A known failure's floor: the smallest count k with P(X <= k) >= 1e-6 for
// X ~ Binomial(n, max_rate / kCapSlack). Fewer in a run says the true rate is
// below a kCapSlack-th of the stated max rate: the cap hides regressions (lower it).
inline constexpr double kCapSlack = 4;
long known_failure_floor(long n, double max_rate);

struct Tally {
  long cases = 0, rays = 0, ok = 0, explained = 0, unexplained = 0, skipped = 0;
  std::map<std::string, long> labels;  // explained/unexplained labels
  std::map<std::string, long> skipped_labels;
  // Units per class (watertight: vertex, edge, face rays), and which class each
  // label was seen in: rates divide by the units of their class.
  std::map<std::string, long> class_rays;
  std::map<std::string, std::string> label_class;  // label -> its class ("*" if several)
  std::map<std::string, std::vector<double>> errors;  // measured errors per unit ("": the property's)
  void add(const Verdict& v);
  // The denominator of a label's rate: the units of its class, or all units.
  std::pair<long, std::string> per(const std::string& label) const;
  static double max_of(const std::vector<double>& e);
  static double p99_of(std::vector<double> e);
  const std::vector<double>* default_errors() const;  // the property's own unit, or null
};

// "label n (x% of m <class> <units>), ..."
std::string labels_text(const std::map<std::string, long>& labels, long rays, const std::string& units,
                        const Tally* t = nullptr);

// Rewrites rows of a CSV keyed by their first key_cols fields, under an exclusive lock
// (ctest runs several test processes at once).
void upsert_csv(const std::string& path, const std::string& header, size_t key_cols,
                const std::vector<std::string>& rows);

// The outcome table of this process, printed at exit.
struct TableRow {
  std::string family, check, generator, pair, impl, units;
  Tally tally;
};
std::vector<TableRow>& table();
void print_table();

}  // namespace lockstep::props::driver

// lockstep props/driver: tallies, the outcome table, CSV rows (see tally.h).
#include "props/driver/tally.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>

namespace lockstep::props::driver {

std::string g3(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", x);
  return buf;
}

long known_failure_cap(long n, double max_rate) {
  if (n <= 0 || max_rate <= 0) return 0;
  if (max_rate >= 1) return n;
  // Upper tail of Binomial(n, p), summed from the pmf in log space.
  const double p = max_rate, lq = std::log1p(-p), lp = std::log(p);
  auto log_pmf = [&](long k) {
    return std::lgamma(double(n) + 1) - std::lgamma(double(k) + 1) - std::lgamma(double(n - k) + 1) + double(k) * lp +
           double(n - k) * lq;
  };
  // P(X >= k+1) < 1e-6: the smallest such k is the cap.
  double tail = 0;
  std::vector<double> pmf(size_t(n) + 1);
  for (long k = 0; k <= n; ++k) pmf[size_t(k)] = std::exp(log_pmf(k));
  for (long k = n; k >= 0; --k) {
    if (tail + pmf[size_t(k)] >= 1e-6) return k;  // P(X >= k) >= 1e-6, P(X >= k+1) < 1e-6
    tail += pmf[size_t(k)];
  }
  return 0;
}

long known_failure_floor(long n, double max_rate) {
  const double q = max_rate / kCapSlack;
  if (n <= 0 || q <= 0) return 0;
  if (q >= 1) return n;
  const double lq = std::log1p(-q), lp = std::log(q);
  double cum = 0;
  for (long k = 0; k <= n; ++k) {
    cum += std::exp(std::lgamma(double(n) + 1) - std::lgamma(double(k) + 1) - std::lgamma(double(n - k) + 1) +
                    double(k) * lp + double(n - k) * lq);
    if (cum >= 1e-6) return k;  // P(X <= k - 1) < 1e-6
  }
  return n;
}

void Tally::add(const Verdict& v) {
  ++cases;
  for (const Outcome& o : v.rays) {
    ++rays;
    if (!o.cls.empty()) ++class_rays[o.cls];
    if (o.kind == Outcome::explained || o.kind == Outcome::unexplained) {
      const std::string l = (o.kind == Outcome::unexplained ? "UNEXPLAINED " : "") + o.label;
      auto [it, fresh] = label_class.emplace(l, o.cls);
      if (!fresh && it->second != o.cls) it->second = "*";
    }
    switch (o.kind) {
      case Outcome::ok: ++ok; break;
      case Outcome::explained: ++explained; ++labels[o.label]; break;
      case Outcome::unexplained: ++unexplained; ++labels["UNEXPLAINED " + o.label]; break;
      case Outcome::skipped: ++skipped; ++skipped_labels[o.label]; break;
    }
    if (o.kind != Outcome::skipped && o.measured && std::isfinite(o.err)) errors[o.unit].push_back(o.err);
  }
}
std::pair<long, std::string> Tally::per(const std::string& label) const {
  auto it = label_class.find(label);
  if (it == label_class.end() || it->second.empty() || it->second == "*") return {rays, ""};
  auto c = class_rays.find(it->second);
  return {c == class_rays.end() ? rays : c->second, it->second};
}
double Tally::max_of(const std::vector<double>& e) { return e.empty() ? 0 : *std::max_element(e.begin(), e.end()); }
double Tally::p99_of(std::vector<double> e) {
  if (e.empty()) return 0;
  const size_t k = std::min(e.size() - 1, size_t(std::ceil(0.99 * double(e.size()))) - 1);
  std::nth_element(e.begin(), e.begin() + long(k), e.end());
  return e[k];
}
const std::vector<double>* Tally::default_errors() const {
  auto it = errors.find("");
  return it == errors.end() ? nullptr : &it->second;
}


void upsert_csv(const std::string& path, const std::string& header, size_t key_cols,
                const std::vector<std::string>& rows) {
  const int fd = ::open(path.c_str(), O_RDWR | O_CREAT, 0644);
  if (fd < 0) {
    std::cerr << "cannot open " << path << "\n";
    return;
  }
  ::flock(fd, LOCK_EX);
  std::string text;
  char buf[4096];
  for (ssize_t n; (n = ::read(fd, buf, sizeof buf)) > 0;) text.append(buf, size_t(n));
  auto key = [&](const std::string& line) {
    size_t pos = 0;
    for (size_t k = 0; k < key_cols && pos != std::string::npos; ++k) pos = line.find(',', pos + (k ? 1 : 0));
    return line.substr(0, pos);
  };
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);)
    if (!l.empty() && l != header) lines.push_back(l);
  for (const std::string& r : rows) {
    auto it = std::find_if(lines.begin(), lines.end(), [&](const std::string& l) { return key(l) == key(r); });
    if (it != lines.end()) *it = r;
    else lines.push_back(r);
  }
  std::string out = header + "\n";
  for (const auto& l : lines) out += l + "\n";
  ::lseek(fd, 0, SEEK_SET);
  if (::ftruncate(fd, 0) != 0 || ::write(fd, out.data(), out.size()) != ssize_t(out.size()))
    std::cerr << "cannot write " << path << "\n";
  ::flock(fd, LOCK_UN);
  ::close(fd);
}

std::vector<TableRow>& table() {
  static std::vector<TableRow> t;
  return t;
}

std::string labels_text(const std::map<std::string, long>& labels, long rays, const std::string& units,
                        const Tally* t) {
  std::string s;
  for (const auto& [l, n] : labels) {
    if (!s.empty()) s += ", ";
    const auto [den, cls] = t ? t->per(l) : std::pair<long, std::string>{rays, ""};
    s += l + " " + std::to_string(n) + " (" + g3(100.0 * double(n) / double(std::max(1L, den))) + "%" +
         (cls.empty() ? "" : " of " + std::to_string(den) + " " + cls + " " + units) + ")";
  }
  return s.empty() ? "-" : s;
}

void print_table() {
  if (table().empty()) return;
  std::cout << "\n==== lockstep props: outcome table (units judged against the oracle) ====\n";
  std::cout << "family | check | generator | pair | impl | cases | units | ok | explained (classified) | unexplained | "
               "skipped | labels\n";
  for (const TableRow& r : table()) {
    const Tally& t = r.tally;
    std::cout << r.family << " | " << r.check << " | " << r.generator << " | " << r.pair << " | " << r.impl << " | "
              << t.cases << " | " << t.rays << " | " << t.ok << " | " << t.explained << " | " << t.unexplained
              << " | " << t.skipped << " | " << labels_text(t.labels, t.rays, r.units, &t) << "\n";
  }
}

}  // namespace lockstep::props::driver

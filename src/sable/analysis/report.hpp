// Results of an analysis as files: CSV tables with units in the headers, and a JSON summary.
//
// Every analysis writes through these two so that all outputs look alike: a Table is a set of
// named columns ("pressure_Pa", "f_over_mean"), a Summary an ordered JSON object of scalars,
// arrays and nested objects. Files are written atomically (never half a file), and a writer
// refuses to replace the snapshot it analyses (see guard_output).
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace sable {

// Mean and sample standard deviation (n - 1; 0 for one row) of value(row) over rows, which
// must not be empty: the per-snapshot series of an analysis summarised.
template <class Row, class F>
std::pair<double, double> mean_sd(const std::vector<Row>& rows, const F& value) {
  const double n = static_cast<double>(rows.size());
  double m = 0.0;
  for (const Row& r : rows) m += value(r);
  m /= n;
  double v = 0.0;
  for (const Row& r : rows) v += (value(r) - m) * (value(r) - m);
  return {m, rows.size() > 1 ? std::sqrt(v / (n - 1.0)) : 0.0};
}

struct Table {
  std::vector<std::string> names;  // with units: "z_m", "sigma_n_Pa"; "-" for none
  std::vector<std::vector<double>> columns;
  void add(std::string name, std::vector<double> values);
  std::size_t rows() const { return columns.empty() ? 0 : columns.front().size(); }
  // CSV text: header line, then rows with 12 significant digits; NaN written as "nan".
  std::string csv() const;
};

class Summary {
 public:
  Summary& add(const std::string& key, double v);  // NaN or inf -> null
  Summary& add(const std::string& key, std::int64_t v);
  Summary& add(const std::string& key, std::size_t v) {
    return add(key, static_cast<std::int64_t>(v));
  }
  Summary& add(const std::string& key, int v) { return add(key, static_cast<std::int64_t>(v)); }
  Summary& add(const std::string& key, bool v);
  Summary& add(const std::string& key, const char* v) { return add(key, std::string(v)); }
  Summary& add(const std::string& key, const std::string& v);
  Summary& add(const std::string& key, const std::vector<double>& v);
  Summary& add(const std::string& key, const Summary& v);
  std::string json(int indent = 0) const;
  bool empty() const { return items_.empty(); }

 private:
  std::vector<std::pair<std::string, std::string>> items_;  // key, rendered JSON value
  std::vector<int> child_;  // index into children_, or -1 for a rendered value
  std::vector<Summary> children_;
};

// Where an analysis writes: a directory, and the inputs it must never overwrite (an analysis
// never writes over the snapshot it reads). Files are replaced atomically.
class ResultWriter {
 public:
  ResultWriter(std::string dir, const std::vector<std::string>& inputs);
  std::string path(const std::string& name) const;
  // Throws InputError naming the file if `name` resolves to one of the inputs.
  void write(const std::string& name, const std::string& text) const;
  void write(const std::string& name, const Table& t) const { write(name, t.csv()); }
  void write(const std::string& name, const Summary& s) const { write(name, s.json() + "\n"); }
  const std::string& dir() const { return dir_; }

 private:
  std::string dir_;
  std::vector<std::string> inputs_;  // canonical paths
};

}  // namespace sable

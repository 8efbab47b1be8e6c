// A Google Benchmark reporter that keeps each benchmark's median (or only run) in
// microseconds, and one that passes runs to two reporters: the console and the collector,
// so a bench can print its own summary table after the usual output.
#pragma once

#include <benchmark/benchmark.h>

#include <map>
#include <string>
#include <vector>

namespace bench {

class Collector : public benchmark::BenchmarkReporter {
 public:
  std::map<std::string, double> median_us;
  bool ReportContext(const Context&) override { return true; }
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs) {
      if (r.run_type == Run::RT_Aggregate && r.aggregate_name != "median") continue;
      const double us = r.GetAdjustedRealTime() *
                        (r.time_unit == benchmark::kMillisecond ? 1000.0 : r.time_unit == benchmark::kNanosecond ? 1e-3 : 1.0);
      median_us[r.run_name.str()] = us;
    }
  }
};

class Tee : public benchmark::BenchmarkReporter {
 public:
  Tee(benchmark::BenchmarkReporter* a, Collector* b) : a_(a), b_(b) {}
  bool ReportContext(const Context& c) override {
    b_->ReportContext(c);
    return a_->ReportContext(c);
  }
  void ReportRuns(const std::vector<Run>& r) override {
    a_->ReportRuns(r);
    b_->ReportRuns(r);
  }
  void Finalize() override { a_->Finalize(); }

 private:
  benchmark::BenchmarkReporter* a_;
  Collector* b_;
};


/// The median of the first benchmark whose name starts with `prefix`, in microseconds (-1: none).
inline double median_us(const Collector& c, const std::string& prefix) {
  for (const auto& [k, v] : c.median_us)
    if (k.rfind(prefix, 0) == 0) return v;
  return -1.0;
}

}  // namespace bench

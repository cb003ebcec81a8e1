// Per-process resource samples from /proc, the C++ twin of procstat.py:
// cumulative CPU time (utime + stime), resident set, open file descriptors
// and threads of a pid. CPU over a window is always the difference of two
// cumulative readings, so it is exact whatever the sampling period.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace mtc::bench {

struct ProcReading {
  double cpu_s = 0;  // utime + stime since the process started
  std::int64_t rss_kb = 0;
  int fds = 0;
  int threads = 0;
};

// Nothing when the process is gone (or /proc cannot be read).
std::optional<ProcReading> read_proc(pid_t pid);

// What one process's DDS side has done, cumulative.
struct DdsCounts {
  std::uint64_t values = 0;            // counterpart values handed to the application
  std::uint64_t samples_received = 0;  // samples its readers took (state + heartbeat)
  std::uint64_t samples_written = 0;   // samples it wrote (state + heartbeat)
};

struct ProcSample {
  double t_s = 0;  // seconds since the run's start
  ProcReading reading;
  std::optional<double> cpu_pct;  // over the interval since the previous sample
  DdsCounts counts;
  // Over the interval since the previous sample.
  std::optional<double> values_per_s;
  std::optional<double> samples_received_per_s;
  std::optional<double> samples_written_per_s;
};

class ProcSeries {
 public:
  ProcSeries(std::string name, pid_t pid) : name_(std::move(name)), pid_(pid) {}

  // Takes one sample; false when the process is gone.
  bool sample(double t_s, const DdsCounts& counts);
  // Mean rates from the first sample to the last (nothing without two).
  std::optional<double> samples_written_per_s() const;
  std::optional<double> samples_received_per_s() const;

  // CPU (% of one core) from the first sample at or after `start_s` to the
  // last at or before `end_s`; nothing without two such samples.
  std::optional<double> cpu_pct_between(double start_s, double end_s) const;
  std::optional<double> first_window_pct(double window_s) const;
  std::optional<double> last_window_pct(double window_s) const;

  // {"name":..., "pid":..., "samples":[...], "cpu_first_window_pct":..., ...}:
  // the schema of benchmarks/endurance/procstat.py, read by plot.py.
  void write_json(std::ostream& out, double window_s) const;

  const std::string& name() const noexcept { return name_; }
  pid_t pid() const noexcept { return pid_; }
  const std::vector<ProcSample>& samples() const noexcept { return samples_; }

 private:
  void write_figures_json(std::ostream& out, double window_s) const;

  std::string name_;
  pid_t pid_;
  std::vector<ProcSample> samples_;
};

// JSON number or null.
std::string json_number(std::optional<double> value, int decimals = 3);

}  // namespace mtc::bench

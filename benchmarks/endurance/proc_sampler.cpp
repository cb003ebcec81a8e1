#include "proc_sampler.hpp"

#include <dirent.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <sstream>

namespace mtc::bench {
namespace {

// Entries of /proc/<pid>/fd, "." and ".." aside; -1 when unreadable. When
// pid is this process, the descriptor opendir holds is not counted.
int count_fds(pid_t pid) {
  const std::string path = "/proc/" + std::to_string(pid) + "/fd";
  DIR* dir = opendir(path.c_str());
  if (dir == nullptr) {
    return -1;
  }
  int n = 0;
  // glibc's readdir is safe on a stream no other thread reads; readdir_r is
  // deprecated.
  while (const dirent* entry = readdir(dir)) {  // NOLINT(concurrency-mt-unsafe)
    if (entry->d_name[0] != '.') {
      ++n;
    }
  }
  closedir(dir);
  return pid == getpid() ? n - 1 : n;
}

}  // namespace

std::optional<ProcReading> read_proc(pid_t pid) {
  std::string stat(1024, '\0');
  const std::string path = "/proc/" + std::to_string(pid) + "/stat";
  std::FILE* f = std::fopen(path.c_str(), "r");
  if (f == nullptr) {
    return std::nullopt;
  }
  stat.resize(std::fread(stat.data(), 1, stat.size(), f));
  std::fclose(f);
  // The command name (field 2) may hold spaces and ')': fields 3.. follow
  // the last ')'.
  const auto close = stat.rfind(')');
  if (stat.empty() || close == std::string::npos) {
    return std::nullopt;
  }
  std::istringstream fields(stat.substr(close + 2));
  std::vector<std::string> field;
  for (std::string word; fields >> word;) {
    field.push_back(word);
  }
  if (field.size() < 22 || field[0] == "Z" || field[0] == "X") {  // gone, not yet reaped
    return std::nullopt;
  }
  static const auto ticks = static_cast<double>(sysconf(_SC_CLK_TCK));
  static const std::int64_t page_kb = sysconf(_SC_PAGESIZE) / 1024;
  ProcReading r;
  r.cpu_s = static_cast<double>(std::stoll(field[11]) + std::stoll(field[12])) / ticks;  // 14, 15
  r.threads = std::stoi(field[17]);                                                      // 20
  r.rss_kb = std::stoll(field[21]) * page_kb;                                            // 24
  r.fds = count_fds(pid);
  if (r.fds < 0) {
    return std::nullopt;
  }
  return r;
}

bool ProcSeries::sample(double t_s, const DdsCounts& counts) {
  const auto reading = read_proc(pid_);
  if (!reading) {
    return false;
  }
  ProcSample s;
  s.t_s = t_s;
  s.reading = *reading;
  s.counts = counts;
  if (!samples_.empty() && t_s > samples_.back().t_s) {
    const ProcSample& prev = samples_.back();
    const double span = t_s - prev.t_s;
    const auto rate = [span](std::uint64_t now, std::uint64_t before) {
      return static_cast<double>(now - before) / span;
    };
    s.cpu_pct = 100.0 * (reading->cpu_s - prev.reading.cpu_s) / span;
    s.values_per_s = rate(counts.values, prev.counts.values);
    s.samples_received_per_s = rate(counts.samples_received, prev.counts.samples_received);
    s.samples_written_per_s = rate(counts.samples_written, prev.counts.samples_written);
  }
  samples_.push_back(s);
  return true;
}

namespace {

std::optional<double> mean_rate(const std::vector<ProcSample>& samples,
                                std::uint64_t DdsCounts::*field) {
  if (samples.size() < 2 || samples.back().t_s <= samples.front().t_s) {
    return std::nullopt;
  }
  return static_cast<double>(samples.back().counts.*field - samples.front().counts.*field) /
         (samples.back().t_s - samples.front().t_s);
}

}  // namespace

std::optional<double> ProcSeries::samples_written_per_s() const {
  return mean_rate(samples_, &DdsCounts::samples_written);
}

std::optional<double> ProcSeries::samples_received_per_s() const {
  return mean_rate(samples_, &DdsCounts::samples_received);
}

std::optional<double> ProcSeries::cpu_pct_between(double start_s, double end_s) const {
  const auto first = std::find_if(samples_.begin(), samples_.end(),
                                  [&](const ProcSample& s) { return s.t_s >= start_s - 0.5; });
  const auto last = std::find_if(samples_.rbegin(), samples_.rend(),
                                 [&](const ProcSample& s) { return s.t_s <= end_s + 0.5; });
  if (first == samples_.end() || last == samples_.rend() || last->t_s <= first->t_s) {
    return std::nullopt;
  }
  return 100.0 * (last->reading.cpu_s - first->reading.cpu_s) / (last->t_s - first->t_s);
}

std::optional<double> ProcSeries::first_window_pct(double window_s) const {
  if (samples_.empty()) {
    return std::nullopt;
  }
  return cpu_pct_between(samples_.front().t_s, samples_.front().t_s + window_s);
}

std::optional<double> ProcSeries::last_window_pct(double window_s) const {
  if (samples_.empty()) {
    return std::nullopt;
  }
  return cpu_pct_between(samples_.back().t_s - window_s, samples_.back().t_s);
}

std::string json_number(std::optional<double> value, int decimals) {
  if (!value) {
    return "null";
  }
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, *value);
  return buf;
}

// RSS, fds and threads at the start, after the first window (the settled
// value to compare the last with), at the end and at most.
void ProcSeries::write_figures_json(std::ostream& out, double window_s) const {
  const double settled_at = samples_.front().t_s + window_s + 0.5;
  const auto settled = std::find_if(samples_.rbegin(), samples_.rend(),
                                    [&](const ProcSample& s) { return s.t_s <= settled_at; });
  const ProcReading& at_window = settled->reading;
  const auto field = [&](const char* name, auto get) {
    std::int64_t most = 0;
    for (const auto& s : samples_) {
      most = std::max<std::int64_t>(most, get(s.reading));
    }
    out << ",\"" << name << "_start\":" << get(samples_.front().reading) << ",\"" << name
        << "_after_first_window\":" << get(at_window) << ",\"" << name
        << "_last\":" << get(samples_.back().reading) << ",\"" << name << "_max\":" << most;
  };
  field("rss_kb", [](const ProcReading& r) { return r.rss_kb; });
  field("fds", [](const ProcReading& r) { return std::int64_t{r.fds}; });
  field("threads", [](const ProcReading& r) { return std::int64_t{r.threads}; });
}

void ProcSeries::write_json(std::ostream& out, double window_s) const {
  out << "{\"name\":\"" << name_ << "\",\"pid\":" << pid_ << ",\"samples\":[";
  for (std::size_t i = 0; i < samples_.size(); ++i) {
    const ProcSample& s = samples_[i];
    out << (i > 0 ? "," : "") << "{\"t_s\":" << json_number(s.t_s)
        << ",\"cpu_s\":" << json_number(s.reading.cpu_s)
        << ",\"cpu_pct\":" << json_number(s.cpu_pct) << ",\"rss_kb\":" << s.reading.rss_kb
        << ",\"fds\":" << s.reading.fds << ",\"threads\":" << s.reading.threads
        << ",\"values_received\":" << s.counts.values
        << ",\"values_per_s\":" << json_number(s.values_per_s, 1)
        << ",\"samples_received\":" << s.counts.samples_received
        << ",\"samples_received_per_s\":" << json_number(s.samples_received_per_s, 1)
        << ",\"samples_written\":" << s.counts.samples_written
        << ",\"samples_written_per_s\":" << json_number(s.samples_written_per_s, 1) << "}";
  }
  out << "]";
  const auto first = first_window_pct(window_s);
  const auto last = last_window_pct(window_s);
  std::optional<double> ratio;
  if (first && last && *first > 0) {
    ratio = *last / *first;
  }
  out << ",\"cpu_first_window_pct\":" << json_number(first)
      << ",\"cpu_last_window_pct\":" << json_number(last)
      << ",\"cpu_ratio_last_to_first\":" << json_number(ratio)
      << ",\"samples_written_per_s\":" << json_number(samples_written_per_s(), 1)
      << ",\"samples_received_per_s\":" << json_number(samples_received_per_s(), 1);
  if (!samples_.empty()) {
    write_figures_json(out, window_s);
  }
  out << "}";
}

}  // namespace mtc::bench

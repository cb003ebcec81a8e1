#include "cyclone_pingpong.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string_view>

namespace mtc::bench {
namespace {

// Cyclone on the loopback interface only, multicast for discovery only: the
// namespace has nothing else, this makes the restriction explicit.
constexpr const char* kLoopbackOnly =
    "<CycloneDDS><Domain id=\"any\"><General><Interfaces><NetworkInterface name=\"lo\"/>"
    "</Interfaces><AllowMulticast>spdp</AllowMulticast></General></Domain></CycloneDDS>";

// Starts ddsperf with `args`; its stdout goes to `out_fd`. Everything the
// child needs is built before fork(): the parent may run other threads.
pid_t spawn_ddsperf(const std::vector<std::string>& args, int out_fd) {
  std::vector<char*> argv{const_cast<char*>("ddsperf")};
  for (const auto& a : args) {
    argv.push_back(const_cast<char*>(a.c_str()));
  }
  argv.push_back(nullptr);
  const std::string uri = std::string("CYCLONEDDS_URI=") + kLoopbackOnly;
  std::vector<char*> envp;
  for (char** e = environ; *e != nullptr; ++e) {
    if (std::string_view(*e).rfind("CYCLONEDDS_URI=", 0) != 0) {
      envp.push_back(*e);
    }
  }
  envp.push_back(const_cast<char*>(uri.c_str()));
  envp.push_back(nullptr);
  const pid_t pid = fork();
  if (pid < 0) {
    throw std::runtime_error("cyclone: fork failed");
  }
  if (pid == 0) {
    prctl(PR_SET_PDEATHSIG, SIGTERM);
    dup2(out_fd, STDOUT_FILENO);
    execvpe("ddsperf", argv.data(), envp.data());
    _exit(127);
  }
  return pid;
}

double cpu_us(const rusage& usage) {
  return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) * 1e6 +
         static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

std::vector<CycloneSecond> parse(const std::string& output) {
  // "... size 12 mean 12.7us min 10.5us 50% 11.5us 90% 12.8us 99% 33.6us max 2082.9us cnt 38307"
  static const std::regex line(
      R"(mean ([0-9.]+)us min ([0-9.]+)us 50% ([0-9.]+)us 90% ([0-9.]+)us 99% ([0-9.]+)us )"
      R"(max ([0-9.]+)us cnt ([0-9]+))");
  std::vector<CycloneSecond> seconds;
  for (std::sregex_iterator it(output.begin(), output.end(), line), end; it != end; ++it) {
    const auto& m = *it;
    CycloneSecond s;
    s.mean = 2 * std::stod(m[1]);
    s.min = 2 * std::stod(m[2]);
    s.p50 = 2 * std::stod(m[3]);
    s.p90 = 2 * std::stod(m[4]);
    s.p99 = 2 * std::stod(m[5]);
    s.max = 2 * std::stod(m[6]);
    s.count = std::stol(m[7]);
    if (s.count > 0) {
      seconds.push_back(s);
    }
  }
  return seconds;
}

std::string read_all(int fd) {
  std::string text;
  char buffer[4096];
  for (;;) {
    const auto n = ::read(fd, buffer, sizeof buffer);
    if (n <= 0) {
      return text;
    }
    text.append(buffer, static_cast<std::size_t>(n));
  }
}

}  // namespace

std::optional<CycloneResult> run_cyclone_round_trips(int domain, int seconds, std::string& why) {
  const std::string dom = std::to_string(domain);
  // ddsperf's -D counts from its start, discovery included: two seconds more
  // so that a slow start on a loaded machine still leaves `seconds` of
  // round trips (its per-second reports come at whole seconds of its clock).
  const std::string ping_seconds = std::to_string(seconds + 2);
  const std::string pong_seconds = std::to_string(seconds + 8);
  CycloneResult result;
  result.command = "ddsperf -i " + dom + " pong & ddsperf -i " + dom + " -D " + ping_seconds +
                   " -Qminmatch:1 -Qinitwait:5 ping";
  int pipe_fds[2];
  const int null_fd = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
  if (null_fd < 0 || ::pipe2(pipe_fds, O_CLOEXEC) != 0) {
    throw std::runtime_error("cyclone: cannot open /dev/null or a pipe");
  }
  const pid_t pong = spawn_ddsperf({"-i", dom, "-D", pong_seconds, "pong"}, null_fd);
  ::close(null_fd);
  const pid_t ping = spawn_ddsperf(
      {"-i", dom, "-D", ping_seconds, "-Qminmatch:1", "-Qinitwait:5", "ping"}, pipe_fds[1]);
  ::close(pipe_fds[1]);
  const std::string output = read_all(pipe_fds[0]);
  ::close(pipe_fds[0]);
  int ping_status = 0;
  rusage ping_usage{};
  ::wait4(ping, &ping_status, 0, &ping_usage);
  ::kill(pong, SIGTERM);
  int pong_status = 0;
  rusage pong_usage{};
  ::wait4(pong, &pong_status, 0, &pong_usage);
  if (WIFEXITED(ping_status) && WEXITSTATUS(ping_status) == 127) {
    why = "ddsperf not installed (Debian cyclonedds-tools)";
    return std::nullopt;
  }
  result.seconds = parse(output);
  if (result.seconds.empty()) {
    why = "ddsperf printed no round trip (exit status " + std::to_string(ping_status) + ")";
    return std::nullopt;
  }
  long count = 0;
  for (const auto& s : result.seconds) {
    count += s.count;
  }
  result.cpu_us_per_op = (cpu_us(ping_usage) + cpu_us(pong_usage)) / static_cast<double>(count);
  return result;
}

double cyclone_median(const CycloneResult& result, double CycloneSecond::*field) {
  std::vector<double> values;
  for (const auto& s : result.seconds) {
    values.push_back(s.*field);
  }
  if (values.empty()) {
    return 0;
  }
  std::sort(values.begin(), values.end());
  return values[(values.size() - 1) / 2];
}

std::string cyclone_json(const std::optional<CycloneResult>& result, const std::string& why) {
  std::ostringstream json;
  if (!result) {
    json << "{\"available\":false,\"why\":\"" << why << "\"}";
    return json.str();
  }
  double worst_p99 = 0;
  double max = 0;
  long count = 0;
  for (const auto& s : result->seconds) {
    worst_p99 = std::max(worst_p99, s.p99);
    max = std::max(max, s.max);
    count += s.count;
  }
  char cpu[32];
  std::snprintf(cpu, sizeof cpu, "%.1f", result->cpu_us_per_op);
  json << "{\"available\":true,\"name\":\"cyclone_round_trip_udp_loopback_2proc\","
          "\"layer\":\"raw_cyclone\",\"metric\":\"round_trip\",\"transport\":\"udp_loopback\","
          "\"processes\":2,\"unit\":\"us\",\"count\":"
       << count << ",\"p50\":" << cyclone_median(*result, &CycloneSecond::p50)
       << ",\"p90\":" << cyclone_median(*result, &CycloneSecond::p90)
       << ",\"p99\":" << cyclone_median(*result, &CycloneSecond::p99)
       << ",\"p99_worst_second\":" << worst_p99 << ",\"max\":" << max
       << ",\"cpu_us_per_op\":" << cpu << ",\"command\":\"" << result->command
       << "\",\"note\":\"ddsperf's per-second percentiles of half the round trip, doubled; "
          "p50/p90/p99 are medians over the seconds (no raw samples, no p99.9); CPU of both "
          "processes includes start-up\",\"seconds\":[";
  for (std::size_t i = 0; i < result->seconds.size(); ++i) {
    const auto& s = result->seconds[i];
    json << (i == 0 ? "" : ",") << "{\"p50\":" << s.p50 << ",\"p90\":" << s.p90
         << ",\"p99\":" << s.p99 << ",\"max\":" << s.max << ",\"count\":" << s.count << "}";
  }
  json << "]}";
  return json.str();
}

}  // namespace mtc::bench

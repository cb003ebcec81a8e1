// Command line of the Google Benchmark executables. benchmark::Initialize
// alone prints the library's terse flag list for --help, ignores -h, and
// leaves every unknown argument for the caller, which then runs anyway; a bad
// --benchmark_format (or _out_format, _color, _time_unit) makes it print that
// list and exit 0. Here --help/-h prints this benchmark's usage and exits 0,
// and anything the library does not take as one of its flags is a usage
// error (one line, the usage on stderr, exit 2), before any benchmark runs.
//
//   if (const auto exit_code = mtc::bench::initialize_google_benchmark(
//           &argc, argv, "mtc-bench-x", "What it measures; where the JSON goes.")) {
//     return *exit_code;
//   }
#pragma once

#include <benchmark/benchmark.h>

#include <cstdlib>
#include <iostream>
#include <optional>
#include <string>
#include <utility>

#include "mtc/bench/cli.hpp"

namespace mtc::bench {

namespace gbench_detail {

// benchmark::Initialize takes its usage printer as a plain function pointer.
inline std::string program;
inline std::string about;

inline void print_usage(std::ostream& out) {
  out << "usage: " << program << " [--benchmark_FLAG=VALUE ...]\n\n"
      << about
      << "\n\nGoogle Benchmark's flags (--name=value; nothing else is accepted):\n"
         "  --benchmark_filter=REGEX       run only the benchmarks matching REGEX (default all)\n"
         "  --benchmark_list_tests=true    list the benchmarks, run none (default false)\n"
         "  --benchmark_min_time=SECONDS   least time each benchmark runs (default 0.5)\n"
         "  --benchmark_min_warmup_time=SECONDS\n"
         "                                 warm-up run before measuring (default 0)\n"
         "  --benchmark_repetitions=N      runs of each benchmark (default 1)\n"
         "  --benchmark_enable_random_interleaving=true|false\n"
         "                                 interleave the repetitions (default false)\n"
         "  --benchmark_report_aggregates_only=true|false\n"
         "                                 only mean/median/stddev of the repetitions, in\n"
         "                                 the table and FILE (default false)\n"
         "  --benchmark_display_aggregates_only=true|false\n"
         "                                 the same in the table only (default false)\n"
         "  --benchmark_out=FILE           also write the results to FILE (default none)\n"
         "  --benchmark_out_format=json|console|csv\n"
         "                                 format of FILE (default json)\n"
         "  --benchmark_format=..., --benchmark_color=..., --benchmark_counters_tabular=...\n"
         "                                 accepted, no effect: stdout always has this\n"
         "                                 benchmark's own table and summary line\n"
         "  --benchmark_context=KEY=VALUE,...\n"
         "                                 extra context in the output (default none)\n"
         "  --benchmark_time_unit=ns|us|ms|s\n"
         "                                 time unit of the results (default per benchmark)\n"
         "  --benchmark_perf_counters=NAME,...\n"
         "                                 hardware counters, if the library has libpfm\n"
         "                                 (default none)\n"
         "  --v=N                          the library's log verbosity (default 0)\n"
         "  -h, --help                     show this text and exit\n";
}

// The library calls this only for a bad value of one of its own flags once
// --help is handled before it; its default would exit 0.
[[noreturn]] inline void reject_flag_value() {
  std::cerr << program
            << ": bad value for a --benchmark_* flag (format, out_format, color, "
               "time_unit)\n\n";
  print_usage(std::cerr);
  // Called while parsing the command line, before any thread exists.
  std::exit(kExitUsage);  // NOLINT(concurrency-mt-unsafe)
}

}  // namespace gbench_detail

// nullopt: the flags are good, run the benchmarks. Otherwise the exit code
// for main() to return: 0 after --help, 2 after a usage error.
inline std::optional<int> initialize_google_benchmark(int* argc, char** argv, std::string program,
                                                      std::string about) {
  gbench_detail::program = std::move(program);
  gbench_detail::about = std::move(about);
  for (int i = 1; i < *argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") {
      gbench_detail::print_usage(std::cout);
      return kExitOk;
    }
  }
  benchmark::Initialize(argc, argv, gbench_detail::reject_flag_value);
  // What the library did not take: an unknown option, or one of its numeric
  // flags with a value it could not parse (it says so on stderr first).
  if (benchmark::ReportUnrecognizedArguments(*argc, argv)) {
    std::cerr << "\n";
    gbench_detail::print_usage(std::cerr);
    return kExitUsage;
  }
  return std::nullopt;
}

}  // namespace mtc::bench

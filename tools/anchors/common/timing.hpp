// What the numeric Pinocchio anchors under tools/anchors/ share: the random stream of the dyngen
// benches (so that both sides time the same states), the timing loop, whose rows the compare
// tools read (`robot nq nv function median_ns min_ns`), and the command line.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace anchor {

// dyngen_runtime::SplitMix64, so that both sides time the same states.
struct SplitMix64 {
  uint64_t s;
  uint64_t next() {
    s += 0x9E3779B97F4A7C15ull;
    uint64_t z = s;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double unit() { return (double)(next() >> 11) / (double)(1ull << 53); }
  double uniform(double lo, double hi) { return lo + (hi - lo) * unit(); }
};

// Keeps a result alive without reading it (Google Benchmark's DoNotOptimize).
template <typename T>
inline void escape(const T &x) {
  asm volatile("" : : "g"(&x) : "memory");
}

// States per robot, as in the dyngen benches.
constexpr int STATES = 256;
constexpr double WARM_UP_SECONDS = 0.2;

// Measurement time per function: `BENCH_SECONDS`, else 1 s.
inline double measure_seconds() {
  static const double seconds = [] {
    const char *s = std::getenv("BENCH_SECONDS");
    return s ? std::atof(s) : 1.0;
  }();
  return seconds;
}

// Times `f(state)` over the states in batches of one call per state; prints the row
// `robot nq nv function median_ns min_ns`, the median and minimum per call over the batches.
template <typename State, typename F>
void time_it(const char *robot, int nq, int nv, const std::string &function,
             const std::vector<State> &xs, F f) {
  using Clock = std::chrono::steady_clock;
  auto batch = [&]() {
    auto t0 = Clock::now();
    for (const State &s : xs) f(s);
    return std::chrono::duration<double, std::nano>(Clock::now() - t0).count() / xs.size();
  };
  auto start = Clock::now();
  while (std::chrono::duration<double>(Clock::now() - start).count() < WARM_UP_SECONDS) batch();
  std::vector<double> per_call;
  start = Clock::now();
  while (per_call.size() < 20 ||
         std::chrono::duration<double>(Clock::now() - start).count() < measure_seconds())
    per_call.push_back(batch());
  std::sort(per_call.begin(), per_call.end());
  size_t n = per_call.size();
  double median = n % 2 ? per_call[n / 2] : 0.5 * (per_call[n / 2 - 1] + per_call[n / 2]);
  std::printf("%s %d %d %s %.2f %.2f\n", robot, nq, nv, function.c_str(), median, per_call[0]);
  std::fflush(stdout);
}

// An anchor's main: `PROGRAM MODELS_DIR [ROBOT...]`, each robot named (every one of `robots` when
// none is) given to `bench(models, robot)` after the header row; 2 for a robot it does not know.
template <typename Robot, size_t N, typename Bench>
int run(int argc, char **argv, const Robot (&robots)[N], const char *version, Bench bench) {
  std::string names;
  for (const Robot &r : robots) names += (names.empty() ? "" : ", ") + std::string(r.name);
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s MODELS_DIR [ROBOT...]  (ROBOT: %s)\n", argv[0], names.c_str());
    return 2;
  }
  const std::string models = argv[1];
  std::vector<std::string> wanted(argv + 2, argv + argc);
  if (wanted.empty())
    for (const Robot &r : robots) wanted.push_back(r.name);
  std::printf("# robot nq nv function median_ns min_ns (Pinocchio %s)\n", version);
  for (const std::string &name : wanted) {
    const Robot *robot = nullptr;
    for (const Robot &r : robots)
      if (name == r.name) robot = &r;
    if (!robot) {
      std::fprintf(stderr, "unknown robot %s (%s)\n", name.c_str(), names.c_str());
      return 2;
    }
    bench(models, *robot);
  }
  return 0;
}

}  // namespace anchor

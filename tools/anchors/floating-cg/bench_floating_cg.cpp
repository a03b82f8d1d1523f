// Numeric Pinocchio 4.1 and Pinocchio 4.1 generated to C by CppADCodeGen (gen.cpp), on free-flyer
// robots: the two anchors of tools/compare_floating.py, whose dyngen side is
// generated/benches/common/floating.rs. See README.md here.
//
//   bench_floating_cg MODELS_DIR [--side pinocchio|cppadcg] [--check] [ROBOT...]
//     (ROBOT: solo12, g1; default both. --side: time one side only; --check: no timing)
//
// Before timing, every generated function is compared with numeric Pinocchio on the first
// CHECK_STATES states: a `# robot check function max_abs_error max_abs_value` line each, and
// exit 1 when an error exceeds 1e-9 of max(1, max_abs_value). Then each side's rows,
// `robot nq nv function median_ns min_ns` (../common/timing.hpp), `function` named alike on both
// sides. Each call is timed over the 256 states of the dyngen bench (the SplitMix64 stream of
// seed 18: base position and quaternion in ±1, the quaternion normalised, joints in ±π, v in ±2,
// a in ±5, tau in ±10), in batches of 256 calls.
#include <pinocchio/algorithm/aba-derivatives.hpp>
#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/algorithm/centroidal.hpp>
#include <pinocchio/algorithm/crba.hpp>
#include <pinocchio/algorithm/rnea-derivatives.hpp>
#include <pinocchio/algorithm/rnea.hpp>
#include <pinocchio/multibody.hpp>

#include "../common/floating_states.hpp"
#include "../common/model_text.hpp"
#include "../common/timing.hpp"
#include "cg_functions.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace pin = pinocchio;
using anchor::escape;

// The seed of generated/benches/common/floating.rs.
static const uint64_t SEED = 18;
static const int CHECK_STATES = 8;

struct Robot {
  const char *name;
};
static const Robot ROBOTS[] = {{"solo12"}, {"g1"}};

// A state for both sides: Pinocchio's vectors, and the generated functions' inputs
// [q, v, a] and [q, v, tau] laid out contiguously.
struct State : anchor::FloatingState {
  std::vector<double> x_a, x_tau;
};

static std::vector<double> concatenated(const Eigen::VectorXd &q, const Eigen::VectorXd &v,
                                        const Eigen::VectorXd &last) {
  std::vector<double> x(q.data(), q.data() + q.size());
  x.insert(x.end(), v.data(), v.data() + v.size());
  x.insert(x.end(), last.data(), last.data() + last.size());
  return x;
}

// common/timing.rs's floating_states.
static std::vector<State> states(const pin::Model &model) {
  std::vector<State> out;
  for (const anchor::FloatingState &drawn : anchor::floating_states(model.nq, model.nv, SEED)) {
    State s;
    static_cast<anchor::FloatingState &>(s) = drawn;
    s.x_a = concatenated(s.q, s.v, s.a);
    s.x_tau = concatenated(s.q, s.v, s.tau);
    out.push_back(s);
  }
  return out;
}

static Eigen::MatrixXd mirrored_upper(Eigen::MatrixXd m) {
  m.triangularView<Eigen::StrictlyLower>() = m.transpose();
  return m;
}

static Eigen::MatrixXd side_by_side(const Eigen::MatrixXd &left, const Eigen::MatrixXd &right) {
  Eigen::MatrixXd out(left.rows(), left.cols() + right.cols());
  out << left, right;
  return out;
}

// A numeric row: the Pinocchio call it times, and where the result is in `Data`, laid out as
// the generated function's output (gen.cpp's FUNCTIONS).
struct Numeric {
  const char *name;
  void (*call)(const pin::Model &, pin::Data &, const State &);
  Eigen::MatrixXd (*result)(const pin::Data &);
};

static const Numeric NUMERIC[] = {
    {"rnea", [](const pin::Model &m, pin::Data &d, const State &s) { pin::rnea(m, d, s.q, s.v, s.a); },
     [](const pin::Data &d) -> Eigen::MatrixXd { return d.tau; }},
    // crba fills the upper triangle only, computeMinverse too: the check mirrors them, the
    // timing does not (as the generated functions' own work includes no mirroring either:
    // CppADCodeGen writes each entry from one expression).
    {"crba", [](const pin::Model &m, pin::Data &d, const State &s) { pin::crba(m, d, s.q); },
     [](const pin::Data &d) { return mirrored_upper(d.M); }},
    {"coriolis",
     [](const pin::Model &m, pin::Data &d, const State &s) { pin::computeCoriolisMatrix(m, d, s.q, s.v); },
     [](const pin::Data &d) -> Eigen::MatrixXd { return d.C; }},
    {"gravity",
     [](const pin::Model &m, pin::Data &d, const State &s) { pin::computeGeneralizedGravity(m, d, s.q); },
     [](const pin::Data &d) -> Eigen::MatrixXd { return d.g; }},
    {"aba", [](const pin::Model &m, pin::Data &d, const State &s) { pin::aba(m, d, s.q, s.v, s.tau); },
     [](const pin::Data &d) -> Eigen::MatrixXd { return d.ddq; }},
    {"minv", [](const pin::Model &m, pin::Data &d, const State &s) { pin::computeMinverse(m, d, s.q); },
     [](const pin::Data &d) { return mirrored_upper(d.Minv); }},
    {"rnea_derivatives",
     [](const pin::Model &m, pin::Data &d, const State &s) {
       pin::computeRNEADerivatives(m, d, s.q, s.v, s.a);
     },
     [](const pin::Data &d) { return side_by_side(d.dtau_dq, d.dtau_dv); }},
    {"aba_derivatives",
     [](const pin::Model &m, pin::Data &d, const State &s) {
       pin::computeABADerivatives(m, d, s.q, s.v, s.tau);
     },
     [](const pin::Data &d) { return side_by_side(d.ddq_dq, d.ddq_dv); }},
    {"ccrba", [](const pin::Model &m, pin::Data &d, const State &s) { pin::computeCentroidalMap(m, d, s.q); },
     [](const pin::Data &d) -> Eigen::MatrixXd { return d.Ag; }},
};

static const Numeric &numeric(const char *name) {
  for (const Numeric &n : NUMERIC)
    if (std::strcmp(n.name, name) == 0) return n;
  std::fprintf(stderr, "no numeric Pinocchio call for the generated function %s\n", name);
  std::exit(1);
}

static const CgRobot &generated(const Robot &r) {
  for (int k = 0; k < cg_robot_count; ++k)
    if (std::strcmp(cg_robots[k].name, r.name) == 0) return cg_robots[k];
  std::fprintf(stderr, "%s: not generated (build.sh's ROBOTS)\n", r.name);
  std::exit(1);
}

static const double *input(const CgFunction &f, const State &s) {
  return (f.inputs == CG_QVTAU ? s.x_tau : s.x_a).data();
}

// Each generated function against its numeric call on the first CHECK_STATES states.
static void check(const pin::Model &model, pin::Data &data, const CgRobot &cg,
                  const std::vector<State> &xs) {
  bool ok = true;
  for (int k = 0; k < cg.function_count; ++k) {
    const CgFunction &f = cg.functions[k];
    const Numeric &n = numeric(f.name);
    std::vector<double> y(f.rows * f.cols);
    double error = 0, scale = 0;
    for (int i = 0; i < CHECK_STATES; ++i) {
      n.call(model, data, xs[i]);
      const Eigen::MatrixXd expected = n.result(data);
      if (expected.rows() != f.rows || expected.cols() != f.cols) {
        std::fprintf(stderr, "%s %s: generated %dx%d, Pinocchio %ldx%ld\n", cg.name, f.name, f.rows,
                     f.cols, (long)expected.rows(), (long)expected.cols());
        std::exit(1);
      }
      std::fill(y.begin(), y.end(), std::nan(""));
      f.call(input(f, xs[i]), y.data());
      const Eigen::Map<const Eigen::MatrixXd> got(y.data(), f.rows, f.cols);
      // NaN in `got` (an entry not written) makes the error NaN, which fails below.
      error = std::max(error, (got - expected).cwiseAbs().maxCoeff());
      if (std::isnan((got - expected).sum())) error = NAN;
      scale = std::max(scale, expected.cwiseAbs().maxCoeff());
    }
    std::printf("# %s check %s %.3e %.3e\n", cg.name, f.name, error, scale);
    if (!(error <= 1e-9 * std::max(1.0, scale))) {
      std::fprintf(stderr, "%s %s: generated and numeric differ by %.3e (max |value| %.3e)\n",
                   cg.name, f.name, error, scale);
      ok = false;
    }
  }
  std::fflush(stdout);
  if (!ok) std::exit(1);
}

static bool time_pinocchio = true, time_cppadcg = true, check_only = false;

static void bench_robot(const std::string &models, const Robot &r) {
  const pin::Model model = anchor::load_model(models, r.name);
  pin::Data data(model);
  const CgRobot &cg = generated(r);
  if (cg.nq != model.nq || cg.nv != model.nv) {
    std::fprintf(stderr, "%s: generated for nq %d, nv %d; the model has nq %d, nv %d\n", r.name,
                 cg.nq, cg.nv, model.nq, model.nv);
    std::exit(1);
  }
  const std::vector<State> xs = states(model);
  check(model, data, cg, xs);
  if (check_only) return;
  if (time_pinocchio) {
    std::printf("# %s: numeric Pinocchio\n", r.name);
    for (int k = 0; k < cg.function_count; ++k) {
      const Numeric &n = numeric(cg.functions[k].name);
      anchor::time_it(r.name, model.nq, model.nv, n.name, xs, [&](const State &s) {
        n.call(model, data, s);
        escape(data);
      });
    }
  }
  if (time_cppadcg) {
    std::printf("# %s: Pinocchio + CppADCodeGen, C compiled with %s\n", r.name, cg_flags);
    for (int k = 0; k < cg.function_count; ++k) {
      const CgFunction &f = cg.functions[k];
      std::vector<double> y(f.rows * f.cols);
      double *out = y.data();
      anchor::time_it(r.name, model.nq, model.nv, f.name, xs, [&](const State &s) {
        f.call(input(f, s), out);
        escape(out);
      });
    }
  }
}

int main(int argc, char **argv) {
  std::vector<char *> rest;
  for (int i = 0; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--check") {
      check_only = true;
    } else if (a == "--side" && i + 1 < argc) {
      const std::string side = argv[++i];
      if (side != "pinocchio" && side != "cppadcg") {
        std::fprintf(stderr, "--side %s: pinocchio or cppadcg\n", side.c_str());
        return 2;
      }
      time_pinocchio = side == "pinocchio";
      time_cppadcg = side == "cppadcg";
    } else {
      rest.push_back(argv[i]);
    }
  }
  return anchor::run((int)rest.size(), rest.data(), ROBOTS, PINOCCHIO_VERSION, bench_robot);
}

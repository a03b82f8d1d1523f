// Numeric Pinocchio 4.1, header-only, timing the named-frame quantities that dyngen generates
// (the group `frames`): the Pinocchio side of tools/compare_frames.py; the dyngen side is
// generated/benches/frames.rs. See README.md here for the build and what each row times.
//
//   bench_frames build/models [ROBOT...]      (ROBOT: panda, ur5; default both)
//
// Prints `robot nq nv function median_ns min_ns`, one row per timed call, `function` being the
// criterion group's `<function>/<frame>` (e.g. `frame_jacobian_local/panda_link8`). Each call
// is timed over the 256 random states of the dyngen bench (the same SplitMix64 stream, seed
// 0x5eed: q in ±π, v ±2, a ±5), in batches of 256 calls; the median and minimum over batches,
// per call.

#include <pinocchio/algorithm/frames.hpp>
#include <pinocchio/algorithm/jacobian.hpp>
#include <pinocchio/algorithm/kinematics.hpp>
#include <pinocchio/algorithm/rnea.hpp>
#include <pinocchio/multibody.hpp>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

namespace pin = pinocchio;
using Clock = std::chrono::steady_clock;

// The robots of generated/benches/frames.rs (their models: dump_model.py): the tool and
// mid-chain frames, and the end-effector of `Kinematics::jacobian`.
struct Robot {
  const char *name;
  const char *tool;
  const char *mid;
  const char *end_effector;
};

static const Robot ROBOTS[] = {
    {"panda", "panda_link8", "panda_link4", "panda_hand_tcp"},
    {"ur5", "ee_link", "forearm_link", "tool0"},
};

// One wrench at the tool frame, LOCAL, [force; moment]: the one of frames.rs.
static const double FORCE[3] = {10.0, -5.0, 20.0};
static const double MOMENT[3] = {0.5, -1.0, 0.25};

static const int STATES = 256;
static const double WARM_UP_SECONDS = 0.2;
static double measure_seconds = 1.0;  // per function; `BENCH_SECONDS` overrides

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

struct State {
  Eigen::VectorXd q, qd, v, a;
};

// benches/common::states: per state, q in ±π, then qd, v in ±2 and a in ±5, N draws each.
static std::vector<State> states(int n) {
  SplitMix64 rng{0x5eed};
  const double pi = 3.14159265358979323846;
  auto draw = [&](double lo, double hi) {
    Eigen::VectorXd x(n);
    for (int i = 0; i < n; ++i) x[i] = rng.uniform(lo, hi);
    return x;
  };
  std::vector<State> out;
  for (int k = 0; k < STATES; ++k) {
    State s;
    s.q = draw(-pi, pi);
    s.qd = draw(-2.0, 2.0);
    s.v = draw(-2.0, 2.0);
    s.a = draw(-5.0, 5.0);
    out.push_back(s);
  }
  return out;
}

// Keeps a result alive without reading it (Google Benchmark's DoNotOptimize).
template <typename T>
static inline void escape(const T &x) {
  asm volatile("" : : "g"(&x) : "memory");
}

// Times `f(state)` over the states in batches of STATES calls; prints the row.
template <typename F>
static void time_it(const char *robot, const pin::Model &model, const std::string &function,
                    const std::vector<State> &xs, F f) {
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
         std::chrono::duration<double>(Clock::now() - start).count() < measure_seconds)
    per_call.push_back(batch());
  std::sort(per_call.begin(), per_call.end());
  size_t n = per_call.size();
  double median = n % 2 ? per_call[n / 2] : 0.5 * (per_call[n / 2 - 1] + per_call[n / 2]);
  std::printf("%s %d %d %s %.2f %.2f\n", robot, model.nq, model.nv, function.c_str(), median,
              per_call[0]);
  std::fflush(stdout);
}

static const char *keyword(pin::ReferenceFrame rf) {
  switch (rf) {
    case pin::LOCAL: return "local";
    case pin::WORLD: return "world";
    default: return "lwa";  // LOCAL_WORLD_ALIGNED, as frames.rs names it
  }
}

static pin::FrameIndex frame_id(const pin::Model &model, const char *name) {
  if (!model.existFrame(name, pin::BODY)) {
    std::fprintf(stderr, "no body frame %s\n", name);
    std::exit(1);
  }
  return model.getFrameId(name, pin::BODY);
}

// Every timed quantity of one frame; the names of generated/benches/frames.rs.
static void bench_frame(const Robot &r, const pin::Model &model, pin::Data &data,
                        const char *name, const std::vector<State> &xs) {
  const pin::FrameIndex fid = frame_id(model, name);
  const std::string at = std::string("/") + name;
  // J and dJ are zeroed once per function, not per call: Pinocchio writes only the columns of
  // the frame's supporting joints, the same ones at every call, so the others stay zero.
  pin::Data::Matrix6x J(6, model.nv), dJ(6, model.nv);

  time_it(r.name, model, "frame_pose" + at, xs, [&](const State &s) {
    pin::forwardKinematics(model, data, s.q);
    escape(pin::updateFramePlacement(model, data, fid));
  });
  for (pin::ReferenceFrame rf : {pin::LOCAL, pin::WORLD, pin::LOCAL_WORLD_ALIGNED}) {
    J.setZero();
    time_it(r.name, model, std::string("frame_jacobian_") + keyword(rf) + at, xs,
            [&](const State &s) {
              pin::computeFrameJacobian(model, data, s.q, fid, rf, J);
              escape(J);
            });
  }
  for (pin::ReferenceFrame rf : {pin::LOCAL, pin::WORLD, pin::LOCAL_WORLD_ALIGNED}) {
    dJ.setZero();
    time_it(r.name, model, std::string("frame_jacobian_time_variation_") + keyword(rf) + at, xs,
            [&](const State &s) {
              pin::computeJointJacobiansTimeVariation(model, data, s.q, s.qd);
              pin::getFrameJacobianTimeVariation(model, data, fid, rf, dJ);
              escape(dJ);
            });
  }
  time_it(r.name, model, "frame_velocity_local" + at, xs, [&](const State &s) {
    pin::forwardKinematics(model, data, s.q, s.qd);
    const pin::Motion m = pin::getFrameVelocity(model, data, fid, pin::LOCAL);
    escape(m);
  });
  time_it(r.name, model, "frame_classical_acceleration_local" + at, xs, [&](const State &s) {
    pin::forwardKinematics(model, data, s.q, s.qd, s.a);
    const pin::Motion m = pin::getFrameClassicalAcceleration(model, data, fid, pin::LOCAL);
    escape(m);
  });
  J.setZero();
  dJ.setZero();
  time_it(r.name, model, "frame_kinematics" + at, xs, [&](const State &s) {
    pin::computeJointJacobiansTimeVariation(model, data, s.q, s.qd);
    escape(pin::updateFramePlacement(model, data, fid));
    pin::getFrameJacobian(model, data, fid, pin::LOCAL_WORLD_ALIGNED, J);
    pin::getFrameJacobianTimeVariation(model, data, fid, pin::LOCAL_WORLD_ALIGNED, dJ);
    escape(J);
    escape(dJ);
  });
}

// Reads build/models/<robot>.txt (dump_model.py): the model the wheel's URDF parser and
// buildReducedModel built, rebuilt here joint by joint and frame by frame.
static pin::Model load(const std::string &models, const Robot &r) {
  const std::string path = models + "/" + r.name + ".txt";
  std::ifstream in(path);
  if (!in) {
    std::fprintf(stderr, "cannot read %s (run build.sh)\n", path.c_str());
    std::exit(1);
  }
  auto read_se3 = [&in]() {
    Eigen::Matrix3d R;
    Eigen::Vector3d p;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) in >> R(i, j);
    in >> p[0] >> p[1] >> p[2];
    return pin::SE3(R, p);
  };
  pin::Model model;
  std::string tag, name;
  size_t joints = 0, frames = 0;
  in >> tag >> model.name >> joints >> frames;
  in >> tag;
  Eigen::Vector3d g;
  in >> g[0] >> g[1] >> g[2];
  model.gravity.linear(g);
  for (size_t k = 0; k < joints; ++k) {
    std::string type;
    pin::JointIndex parent;
    in >> tag >> name >> type >> parent;
    const pin::SE3 placement = read_se3();
    double mass;
    Eigen::Vector3d lever;
    Eigen::Matrix3d inertia;
    in >> mass >> lever[0] >> lever[1] >> lever[2];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) in >> inertia(i, j);
    pin::JointIndex id;
    if (type == "JointModelRX") id = model.addJoint(parent, pin::JointModelRX(), placement, name);
    else if (type == "JointModelRY") id = model.addJoint(parent, pin::JointModelRY(), placement, name);
    else if (type == "JointModelRZ") id = model.addJoint(parent, pin::JointModelRZ(), placement, name);
    else if (type == "JointModelPX") id = model.addJoint(parent, pin::JointModelPX(), placement, name);
    else if (type == "JointModelPY") id = model.addJoint(parent, pin::JointModelPY(), placement, name);
    else if (type == "JointModelPZ") id = model.addJoint(parent, pin::JointModelPZ(), placement, name);
    else {
      std::fprintf(stderr, "%s: joint %s of type %s\n", path.c_str(), name.c_str(), type.c_str());
      std::exit(1);
    }
    model.appendBodyToJoint(id, pin::Inertia(mass, lever, inertia));
  }
  for (size_t k = 0; k < frames; ++k) {
    int type;
    pin::JointIndex parent_joint;
    pin::FrameIndex parent_frame;
    in >> tag >> name >> type >> parent_joint >> parent_frame;
    const pin::SE3 placement = read_se3();
    model.addFrame(pin::Frame(name, parent_joint, parent_frame, placement, (pin::FrameType)type),
                   false);
  }
  if (!in || (frames > 0 && tag != "frame")) {
    std::fprintf(stderr, "%s: malformed\n", path.c_str());
    std::exit(1);
  }
  return model;
}

static void bench_robot(const std::string &models, const Robot &r) {
  const pin::Model model = load(models, r);
  pin::Data data(model);
  const std::vector<State> xs = states(model.nv);

  bench_frame(r, model, data, r.tool, xs);
  bench_frame(r, model, data, r.mid, xs);

  // rnea with the wrench at the tool frame as its joint's fext (a force on the body about the
  // joint origin, in joint axes): converted in each call, as dyngen converts it.
  const pin::FrameIndex tool = frame_id(model, r.tool);
  const pin::Frame &frame = model.frames[tool];
  const pin::Force wrench(Eigen::Vector3d(FORCE[0], FORCE[1], FORCE[2]),
                          Eigen::Vector3d(MOMENT[0], MOMENT[1], MOMENT[2]));
  std::vector<pin::Force> fext((size_t)model.njoints, pin::Force::Zero());
  time_it(r.name, model, std::string("inverse_dynamics_with_wrenches/") + r.tool, xs,
          [&](const State &s) {
            fext[frame.parentJoint] = frame.placement.act(wrench);
            escape(pin::rnea(model, data, s.q, s.qd, s.a, fext));
          });

  // `Kinematics::jacobian`: the end-effector's LOCAL_WORLD_ALIGNED Jacobian.
  const pin::FrameIndex ee = frame_id(model, r.end_effector);
  pin::Data::Matrix6x J = pin::Data::Matrix6x::Zero(6, model.nv);
  time_it(r.name, model, std::string("jacobian/") + r.end_effector, xs, [&](const State &s) {
    pin::computeFrameJacobian(model, data, s.q, ee, pin::LOCAL_WORLD_ALIGNED, J);
    escape(J);
  });
}

int main(int argc, char **argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s MODELS_DIR [ROBOT...]  (ROBOT: panda, ur5)\n", argv[0]);
    return 2;
  }
  if (const char *seconds = std::getenv("BENCH_SECONDS")) measure_seconds = std::atof(seconds);
  const std::string models = argv[1];
  std::vector<std::string> wanted(argv + 2, argv + argc);
  if (wanted.empty()) wanted = {"panda", "ur5"};
  std::printf("# robot nq nv function median_ns min_ns (Pinocchio %s)\n", PINOCCHIO_VERSION);
  for (const std::string &name : wanted) {
    const Robot *robot = nullptr;
    for (const Robot &r : ROBOTS)
      if (name == r.name) robot = &r;
    if (!robot) {
      std::fprintf(stderr, "unknown robot %s (panda, ur5)\n", name.c_str());
      return 2;
    }
    bench_robot(models, *robot);
  }
  return 0;
}

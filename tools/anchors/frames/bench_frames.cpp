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

#include "../common/model_text.hpp"
#include "../common/timing.hpp"

#include <cstdio>
#include <string>
#include <vector>

namespace pin = pinocchio;
using anchor::escape;

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

struct State {
  Eigen::VectorXd q, qd, v, a;
};

// benches/common::states: per state, q in ±π, then qd, v in ±2 and a in ±5, N draws each.
static std::vector<State> states(int n) {
  anchor::SplitMix64 rng{0x5eed};
  const double pi = 3.14159265358979323846;
  auto draw = [&](double lo, double hi) {
    Eigen::VectorXd x(n);
    for (int i = 0; i < n; ++i) x[i] = rng.uniform(lo, hi);
    return x;
  };
  std::vector<State> out;
  for (int k = 0; k < anchor::STATES; ++k) {
    State s;
    s.q = draw(-pi, pi);
    s.qd = draw(-2.0, 2.0);
    s.v = draw(-2.0, 2.0);
    s.a = draw(-5.0, 5.0);
    out.push_back(s);
  }
  return out;
}

// Times `f(state)` over the states; prints the row (anchor::time_it).
template <typename F>
static void time_it(const char *robot, const pin::Model &model, const std::string &function,
                    const std::vector<State> &xs, F f) {
  anchor::time_it(robot, model.nq, model.nv, function, xs, f);
}

static const char *keyword(pin::ReferenceFrame rf) {
  switch (rf) {
    case pin::LOCAL: return "local";
    case pin::WORLD: return "world";
    default: return "lwa";  // LOCAL_WORLD_ALIGNED, as frames.rs names it
  }
}

// Every timed quantity of one frame; the names of generated/benches/frames.rs.
static void bench_frame(const Robot &r, const pin::Model &model, pin::Data &data,
                        const char *name, const std::vector<State> &xs) {
  const pin::FrameIndex fid = anchor::body_frame(model, name);
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

static void bench_robot(const std::string &models, const Robot &r) {
  const pin::Model model = anchor::load_model(models, r.name);
  pin::Data data(model);
  const std::vector<State> xs = states(model.nv);

  bench_frame(r, model, data, r.tool, xs);
  bench_frame(r, model, data, r.mid, xs);

  // rnea with the wrench at the tool frame as its joint's fext (a force on the body about the
  // joint origin, in joint axes): converted in each call, as dyngen converts it.
  const pin::FrameIndex tool = anchor::body_frame(model, r.tool);
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
  const pin::FrameIndex ee = anchor::body_frame(model, r.end_effector);
  pin::Data::Matrix6x J = pin::Data::Matrix6x::Zero(6, model.nv);
  time_it(r.name, model, std::string("jacobian/") + r.end_effector, xs, [&](const State &s) {
    pin::computeFrameJacobian(model, data, s.q, ee, pin::LOCAL_WORLD_ALIGNED, J);
    escape(J);
  });
}

int main(int argc, char **argv) {
  return anchor::run(argc, argv, ROBOTS, PINOCCHIO_VERSION, bench_robot);
}

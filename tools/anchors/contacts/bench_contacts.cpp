// Numeric Pinocchio 4.1, header-only, timing constrained dynamics on rigid contacts: the
// Pinocchio side of tools/compare_contacts.py. The dyngen side is
// generated/benches/common/constrained.rs (Solo-12: generated/benches/contacts.rs; the G1:
// dyngen/ here). See README.md here for the build and what each row times.
//
//   bench_contacts build/models [ROBOT...]      (ROBOT: solo12, g1; default both)
//
// Prints `robot nq nv function median_ns min_ns`, one row per timed call, `function` being the
// criterion group without the robot (`constrained_forward_dynamics` for the group
// `solo12/constrained_forward_dynamics`), and `#` lines: the proximal solve's mean iterations
// and, per function, a check sum (the sum over the states of the result's norm) that the dyngen
// bench prints too, so that a comparison can see both sides compute the same thing on the same
// states. Each call is timed over 256 random states (the stream of the dyngen bench, seed 18),
// in batches of 256 calls; the median and minimum over batches, per call.

#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/algorithm/cholesky.hpp>
#include <pinocchio/algorithm/constrained-dynamics-derivatives.hpp>
#include <pinocchio/algorithm/constrained-dynamics.hpp>
#include <pinocchio/algorithm/crba.hpp>
#include <pinocchio/algorithm/delassus.hpp>
#include <pinocchio/algorithm/frames.hpp>
#include <pinocchio/algorithm/impulse-dynamics.hpp>
#include <pinocchio/algorithm/jacobian.hpp>
#include <pinocchio/algorithm/kinematics.hpp>
#include <pinocchio/algorithm/rnea.hpp>
#include <pinocchio/multibody.hpp>

#include "../common/floating_states.hpp"
#include "../common/model_text.hpp"
#include "../common/timing.hpp"

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace pin = pinocchio;
using anchor::escape;

// The settings of common/constrained.rs, each under the same name.
static const uint64_t SEED = 18;
static const double KP = 10.0;
static const double KD = 2.0 * std::sqrt(KP);
static const double RESTITUTION = 0.5;
static const double ANCHOR_SHIFT[3] = {0.01, -0.02, 0.015};
static const double ANCHOR_TURN = 0.02;
static const double PROXIMAL_MU = 1e-4;
static const int PROXIMAL_MAX_ITERATIONS = 50;
static const double PROXIMAL_ACCURACY = 1e-10;

struct Contact {
  const char *frame;
  pin::ContactType type;
  pin::ReferenceFrame reference;
};

// The contacts of robots/solo12.yaml and of dyngen/g1.yaml, in their order.
struct Robot {
  const char *name;
  std::vector<Contact> contacts;
};

static const Robot ROBOTS[] = {
    {"solo12",
     {{"FL_FOOT", pin::CONTACT_3D, pin::LOCAL},
      {"FR_FOOT", pin::CONTACT_3D, pin::LOCAL_WORLD_ALIGNED},
      {"HL_FOOT", pin::CONTACT_3D, pin::LOCAL},
      {"HR_FOOT", pin::CONTACT_3D, pin::LOCAL_WORLD_ALIGNED}}},
    {"g1",
     {{"left_ankle_roll_link", pin::CONTACT_6D, pin::LOCAL},
      {"right_ankle_roll_link", pin::CONTACT_6D, pin::LOCAL_WORLD_ALIGNED}}},
};

struct State {
  Eigen::VectorXd q, v, tau;
  std::vector<pin::SE3> anchors;
};

// common/timing.rs's floating_states (the acceleration drawn, unused here), and
// common/constrained.rs's anchors: each contact's frame pose, turned about its own x axis and
// moved along the world's.
static std::vector<State> states(const pin::Model &model, pin::Data &data,
                                 const std::vector<pin::FrameIndex> &frames) {
  const Eigen::Matrix3d turn =
      Eigen::AngleAxisd(ANCHOR_TURN, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const Eigen::Vector3d shift(ANCHOR_SHIFT[0], ANCHOR_SHIFT[1], ANCHOR_SHIFT[2]);
  std::vector<State> out;
  for (const anchor::FloatingState &drawn : anchor::floating_states(model.nq, model.nv, SEED)) {
    State s{drawn.q, drawn.v, drawn.tau, {}};
    pin::framesForwardKinematics(model, data, s.q);
    for (pin::FrameIndex f : frames) {
      const pin::SE3 &at = data.oMf[f];
      s.anchors.push_back(pin::SE3(at.rotation() * turn, at.translation() + shift));
    }
    out.push_back(s);
  }
  return out;
}

typedef std::vector<pin::RigidConstraintModel> Models;
typedef std::vector<pin::RigidConstraintData> Datas;

// Each contact held to the world (the second joint the universe), with Baumgarte gains or none.
static Models constraint_models(const pin::Model &model, const Robot &r,
                                const std::vector<pin::FrameIndex> &frames, bool gains) {
  Models out;
  for (size_t k = 0; k < frames.size(); ++k) {
    const pin::Frame &frame = model.frames[frames[k]];
    pin::RigidConstraintModel cm(r.contacts[k].type, model, frame.parentJoint, frame.placement, 0,
                                 pin::SE3::Identity(), r.contacts[k].reference);
    if (gains) {
      cm.m_baumgarte_parameters.Kp = KP;
      cm.m_baumgarte_parameters.Kd = KD;
    }
    out.push_back(cm);
  }
  return out;
}

static Datas constraint_datas(const Models &models) {
  Datas out;
  for (const auto &cm : models) out.push_back(pin::RigidConstraintData(cm));
  return out;
}

static int rows(const Robot &r) {
  int n = 0;
  for (const Contact &c : r.contacts) n += c.type == pin::CONTACT_3D ? 3 : 6;
  return n;
}

// Where a call left its result (Pinocchio's `Data`, or a matrix kept between calls): timed
// calls hand it back for `escape`, the check sums take its norm.
struct Result {
  const double *values;
  Eigen::Index rows, cols;
  double norm() const { return Eigen::Map<const Eigen::MatrixXd>(values, rows, cols).norm(); }
};

template <typename M>
static Result result(const Eigen::MatrixBase<M> &m) {
  return {m.derived().data(), m.rows(), m.cols()};
}

// The calls each row times, on one robot.
struct Calls {
  const pin::Model &model;
  pin::Data &data;
  const Robot &robot;
  const std::vector<pin::FrameIndex> &frames;
  Models plain, stabilised;
  Datas plain_data, stabilised_data;
  pin::ProximalSettings exact, proximal, impulse;
  std::vector<Eigen::MatrixXd> J6;
  Eigen::MatrixXd J, response, inertia, delassus;
  Eigen::LLT<Eigen::MatrixXd> llt;
  Eigen::VectorXd drift, zero;

  Calls(const pin::Model &model, pin::Data &data, const Robot &robot,
        const std::vector<pin::FrameIndex> &frames)
      : model(model),
        data(data),
        robot(robot),
        frames(frames),
        plain(constraint_models(model, robot, frames, false)),
        stabilised(constraint_models(model, robot, frames, true)),
        plain_data(constraint_datas(plain)),
        stabilised_data(constraint_datas(stabilised)),
        exact(),
        proximal(PROXIMAL_ACCURACY, PROXIMAL_MU, PROXIMAL_MAX_ITERATIONS),
        impulse(1e-12, 0.0, 1),
        // Zeroed once, one per contact: Pinocchio writes only the columns of a frame's
        // supporting joints, the same at every call (its documented "fill J with zeros" at no
        // cost per call).
        J6(frames.size(), Eigen::MatrixXd::Zero(6, model.nv)),
        J(Eigen::MatrixXd::Zero(rows(robot), model.nv)),
        response(model.nv, rows(robot)),
        inertia(rows(robot), rows(robot)),
        delassus(rows(robot), rows(robot)),
        llt(rows(robot)),
        drift(rows(robot)),
        zero(Eigen::VectorXd::Zero(model.nv)) {
    // Once, outside the timing: the sizes of the solve's workspace.
    pin::initConstraintDynamics(model, data, plain, plain_data);
  }

  Result forward(const State &s) {
    return result(
        pin::constraintDynamics(model, data, s.q, s.v, s.tau, plain, plain_data, exact));
  }
  Result forward_baumgarte(const State &s) {
    for (size_t k = 0; k < stabilised.size(); ++k) stabilised[k].joint2_placement = s.anchors[k];
    return result(pin::constraintDynamics(model, data, s.q, s.v, s.tau, stabilised,
                                          stabilised_data, exact));
  }
  Result forward_proximal(const State &s) {
    return result(
        pin::constraintDynamics(model, data, s.q, s.v, s.tau, plain, plain_data, proximal));
  }
  // The derivatives at the exact solution, which they need first (dyngen's row likewise solves,
  // then differentiates); the check sum is ∂a/∂q's norm.
  Result forward_derivatives(const State &s) {
    pin::constraintDynamics(model, data, s.q, s.v, s.tau, plain, plain_data, exact);
    pin::computeConstraintDynamicsDerivatives(model, data, plain, plain_data);
    return result(data.ddq_dq);
  }
  Result impact(const State &s) {
    return result(
        pin::impulseDynamics(model, data, s.q, s.v, plain, plain_data, RESTITUTION, impulse));
  }
  // Λ from Pinocchio's constrained Cholesky factor of [[-μI, J], [Jᵀ, M]] (μ = 0), as its
  // derivatives compute it (slower than the Delassus way on Solo-12, alike on the G1): crba in world convention also leaves the joint Jacobians and
  // placements the constraint rows are read from.
  Result inertia_cholesky(const State &s) {
    pin::crba(model, data, s.q, pin::Convention::WORLD);
    for (size_t k = 0; k < plain.size(); ++k) plain[k].calc(model, data, plain_data[k]);
    data.constraint_chol.compute(model, data, plain, plain_data, 0.0);
    data.constraint_chol.getOperationalSpaceInertiaMatrix(inertia);
    return result(inertia);
  }
  // Λ as the inverse of the Delassus matrix J M⁻¹ Jᵀ that Pinocchio computes in linear time.
  // computeDelassusMatrix fills the upper triangle, and writes every contact's rows in its
  // frame's own axes whatever its reference: the lower triangle is mirrored, and a
  // LOCAL_WORLD_ALIGNED contact's rows and columns turned into world axes (R per three rows:
  // the point is the same, only the axes change).
  Result inertia_delassus(const State &s) {
    pin::computeDelassusMatrix(model, data, s.q, plain, plain_data, delassus, 0.0);
    delassus.triangularView<Eigen::StrictlyLower>() = delassus.transpose();
    int row = 0;
    for (size_t k = 0; k < plain.size(); ++k) {
      const int size = robot.contacts[k].type == pin::CONTACT_3D ? 3 : 6;
      if (robot.contacts[k].reference == pin::LOCAL_WORLD_ALIGNED) {
        const Eigen::Matrix3d R = plain_data[k].oMc1.rotation();
        for (int block = row; block < row + size; block += 3) {
          delassus.middleRows<3>(block) = R * delassus.middleRows<3>(block);
          delassus.middleCols<3>(block) = delassus.middleCols<3>(block) * R.transpose();
        }
      }
      row += size;
    }
    llt.compute(delassus);
    inertia.setIdentity();
    llt.solveInPlace(inertia);
    return result(inertia);
  }
  // J from the frames' Jacobians, a point's three linear rows.
  Result jacobian_frames(const State &s) {
    pin::computeJointJacobians(model, data, s.q);
    int row = 0;
    for (size_t k = 0; k < frames.size(); ++k) {
      const Contact &c = robot.contacts[k];
      if (c.type == pin::CONTACT_6D) {
        pin::getFrameJacobian(model, data, frames[k], c.reference, J.middleRows<6>(row));
        row += 6;
      } else {
        pin::getFrameJacobian(model, data, frames[k], c.reference, J6[k]);
        J.middleRows<3>(row) = J6[k].topRows<3>();
        row += 3;
      }
    }
    return result(J);
  }
  // J from the constraint models (getConstraintsJacobian).
  Result jacobian_constraints(const State &s) {
    pin::computeJointJacobians(model, data, s.q);
    for (size_t k = 0; k < plain.size(); ++k) plain[k].calc(model, data, plain_data[k]);
    pin::getConstraintsJacobian(model, data, plain, plain_data, J);
    return result(J);
  }
  // The rows' acceleration at a = 0: a point's classical acceleration, a frame's spatial one.
  Result contact_drift(const State &s) {
    pin::forwardKinematics(model, data, s.q, s.v, zero);
    int row = 0;
    for (size_t k = 0; k < frames.size(); ++k) {
      const Contact &c = robot.contacts[k];
      if (c.type == pin::CONTACT_6D) {
        drift.segment<6>(row) =
            pin::getFrameAcceleration(model, data, frames[k], c.reference).toVector();
        row += 6;
      } else {
        drift.segment<3>(row) =
            pin::getFrameClassicalAcceleration(model, data, frames[k], c.reference).linear();
        row += 3;
      }
    }
    return result(drift);
  }
  // M⁻¹ Jᵀ: crba (world convention: the joint Jacobians too), the rows, Pinocchio's sparse
  // Cholesky factor of M and its solve on each column of Jᵀ.
  Result contact_response(const State &s) {
    pin::crba(model, data, s.q, pin::Convention::WORLD);
    for (size_t k = 0; k < plain.size(); ++k) plain[k].calc(model, data, plain_data[k]);
    pin::getConstraintsJacobian(model, data, plain, plain_data, J);
    pin::cholesky::decompose(model, data);
    response = J.transpose();
    pin::cholesky::solve(model, data, response);
    return result(response);
  }
  Result free_acceleration(const State &s) {
    return result(pin::aba(model, data, s.q, s.v, s.tau));
  }
};

// The timed rows: name (the criterion group's function) and call.
typedef Result (Calls::*Call)(const State &);
struct Row {
  const char *name;
  Call call;
};

static const Row ROWS[] = {
    {"constrained_forward_dynamics", &Calls::forward},
    {"constrained_forward_dynamics_baumgarte", &Calls::forward_baumgarte},
    {"constrained_forward_dynamics_proximal", &Calls::forward_proximal},
    {"impulse_dynamics", &Calls::impact},
    {"operational_space_inertia", &Calls::inertia_delassus},
    {"operational_space_inertia_cholesky", &Calls::inertia_cholesky},
    {"contact_jacobian", &Calls::jacobian_frames},
    {"contact_jacobian_constraints", &Calls::jacobian_constraints},
    {"contact_drift", &Calls::contact_drift},
    {"contact_response", &Calls::contact_response},
    {"free_acceleration", &Calls::free_acceleration},
    {"constrained_forward_dynamics_derivatives", &Calls::forward_derivatives},
};

// Before timing: the rows agree with each other where they compute one thing two ways, and
// with the equations the solves satisfy; each failure a line on stderr, and exit 1.
static void check(Calls &c, const std::vector<State> &xs) {
  bool ok = true;
  auto expect = [&](const char *what, double error, double scale) {
    const double relative = error / std::max(scale, 1.0);
    if (!(relative < 1e-8)) {
      std::fprintf(stderr, "%s: %s off by %.3g (relative)\n", c.robot.name, what, relative);
      ok = false;
    }
  };
  for (size_t k = 0; k < 4; ++k) {
    const State &s = xs[k];
    c.jacobian_constraints(s);
    const Eigen::MatrixXd J = c.J;
    c.jacobian_frames(s);
    expect("J (frames) against J (constraints)", (c.J - J).norm(), J.norm());
    c.contact_drift(s);
    const Eigen::VectorXd drift = c.drift;
    const Eigen::VectorXd a =
        pin::constraintDynamics(c.model, c.data, s.q, s.v, s.tau, c.plain, c.plain_data, c.exact);
    expect("J a + drift = 0", (J * a + drift).norm(), drift.norm());
    pin::crba(c.model, c.data, s.q);
    Eigen::MatrixXd M = c.data.M;
    M.triangularView<Eigen::StrictlyLower>() = M.transpose();
    const Eigen::MatrixXd response = M.llt().solve(J.transpose());
    c.contact_response(s);
    expect("M⁻¹ Jᵀ", (c.response - response).norm(), response.norm());
    const Eigen::MatrixXd inertia = (J * response).inverse();
    c.inertia_cholesky(s);
    expect("Λ (Cholesky)", (c.inertia - inertia).norm(), inertia.norm());
    c.inertia_delassus(s);
    expect("Λ (Delassus)", (c.inertia - inertia).norm(), inertia.norm());
    const Eigen::VectorXd after = pin::impulseDynamics(c.model, c.data, s.q, s.v, c.plain,
                                                       c.plain_data, RESTITUTION, c.impulse);
    expect("J v⁺ = −r J v⁻", (J * after + RESTITUTION * (J * s.v)).norm(), (J * s.v).norm());
  }
  if (!ok) std::exit(1);
}

static void bench_robot(const std::string &models, const Robot &r) {
  const pin::Model model = anchor::load_model(models, r.name);
  pin::Data data(model);
  std::vector<pin::FrameIndex> frames;
  for (const Contact &c : r.contacts) frames.push_back(anchor::body_frame(model, c.frame));
  const std::vector<State> xs = states(model, data, frames);
  Calls calls(model, data, r, frames);
  check(calls, xs);

  double iterations = 0.0;
  for (const State &s : xs) {
    calls.forward_proximal(s);
    iterations += calls.proximal.iter;
  }
  std::printf("# %s proximal_iterations %.2f\n", r.name, iterations / xs.size());
  for (const Row &row : ROWS) {
    double sum = 0.0;
    for (const State &s : xs) sum += (calls.*row.call)(s).norm();
    std::printf("# %s check %s %.12e\n", r.name, row.name, sum);
  }
  for (const Row &row : ROWS)
    anchor::time_it(r.name, model.nq, model.nv, row.name, xs,
                    [&](const State &s) { escape((calls.*row.call)(s)); });
}

int main(int argc, char **argv) {
  return anchor::run(argc, argv, ROBOTS, PINOCCHIO_VERSION, bench_robot);
}

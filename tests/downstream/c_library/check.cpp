// The C++17 program of tests/suite/c_library.rs: every function of every linked robot through
// P_evaluate, all states at once (four per call where the robot has lanes), and a controller's
// tick with Eigen over the Panda and the Solo-12 linked into one program: the model-based
// torque D q̈ + C q̇ + g checked against inverse dynamics, and the torque with a wrench at a
// frame, written for the test to compare with the generic Rust dynamics.
//
// Usage: check_cpp RESULTS STATES...   (exit status 0 when every check holds)
#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "harness.h"
#include "panda_dynamics.h"
#include "solo12_dynamics.h"

namespace {

// What a controller tick calls, for a robot of NQ configuration and NV velocity entries.
template <int NQ, int NV>
struct Dynamics {
    int32_t (*mass_matrix)(const double *q, double *mass_matrix);
    int32_t (*coriolis_matrix)(const double *q, const double *qd, double *coriolis_matrix);
    int32_t (*gravity)(const double *q, double *gravity);
    int32_t (*inverse_dynamics)(const double *q, const double *qd, const double *qdd, double *tau);
    int32_t (*frame_jacobian)(size_t frame, const double *q, double *jacobian);  // LOCAL_WORLD_ALIGNED
};

template <int N>
using Vector = Eigen::Matrix<double, N, 1>;

// The torque that gives q̈ while the wrench w = [force; moment] (base axes, at the frame's
// origin) acts on `frame`: D q̈ + C q̇ + g − Jᵀ w, each matrix read in place with Eigen::Map.
template <int NQ, int NV>
Vector<NV> tick(const Dynamics<NQ, NV> &robot, const double *q, const double *qd, const double *qdd, size_t frame,
                const Vector<6> &wrench) {
    Eigen::Matrix<double, NV, NV> D, C;  // column-major, as the library writes
    Vector<NV> g, tau;
    Eigen::Matrix<double, 6, NV> J;
    if (robot.mass_matrix(q, D.data()) != DYNGEN_OK || robot.coriolis_matrix(q, qd, C.data()) != DYNGEN_OK ||
        robot.gravity(q, g.data()) != DYNGEN_OK || robot.inverse_dynamics(q, qd, qdd, tau.data()) != DYNGEN_OK ||
        robot.frame_jacobian(frame, q, J.data()) != DYNGEN_OK) {
        harness_fail("a controller tick's call failed");
    }
    Eigen::Map<const Vector<NV>> velocity(qd), acceleration(qdd);
    Vector<NV> model = D * acceleration + C * velocity + g;
    double scale = std::max(1.0, tau.cwiseAbs().maxCoeff());
    if ((model - tau).cwiseAbs().maxCoeff() > 1e-12 * scale || (D - D.transpose()).cwiseAbs().maxCoeff() > 1e-12 * scale) {
        harness_fail("D q̈ + C q̇ + g differs from inverse dynamics, or D is not symmetric");
    }
    return tau - J.transpose() * wrench;
}

const Dynamics<PANDA_NQ, PANDA_NV> panda{panda_mass_matrix, panda_coriolis_matrix, panda_gravity,
                                          panda_inverse_dynamics, panda_frame_jacobian_local_world_aligned};
const Dynamics<SOLO12_NQ, SOLO12_NV> solo12{solo12_mass_matrix, solo12_coriolis_matrix, solo12_gravity,
                                             solo12_inverse_dynamics, solo12_frame_jacobian_local_world_aligned};

// Every entry of the robot's table on all the states at once, into Eigen matrices whose
// column s is state s's block of an output.
void batches(FILE *results, const harness_states &states) {
    const harness_robot &robot = *states.robot;
    const auto batch = static_cast<Eigen::Index>(states.batch);
    for (size_t f = 0; f < robot.function_count(); ++f) {
        const dyngen_function_info &info = *robot.function_info(f);
        std::vector<const double *> inputs;
        for (size_t k = 0; k < info.input_count; ++k) {
            inputs.push_back(harness_input(&states, &info.inputs[k]));
        }
        for (size_t frame = 0; frame < harness_frames(&robot, &info); ++frame) {
            std::vector<Eigen::MatrixXd> outputs;
            std::vector<double *> pointers;
            for (size_t k = 0; k < info.output_count; ++k) {
                outputs.emplace_back(static_cast<Eigen::Index>(info.outputs[k].rows * info.outputs[k].cols), batch);
                outputs.back().setConstant(std::nan(""));
                pointers.push_back(outputs.back().data());
            }
            if (robot.evaluate(f, frame, states.batch, inputs.data(), pointers.data()) != DYNGEN_OK) {
                harness_fail("%s: evaluate %s failed", robot.prefix, info.name);
            }
            for (const Eigen::MatrixXd &output : outputs) {
                if (!output.allFinite()) {
                    harness_fail("%s: evaluate %s left an entry unwritten", robot.prefix, info.name);
                }
            }
            harness_write_result(results, "batch", &states, &info, frame, pointers.data());
        }
    }
}

// The controller's tick at every state, its torques written as the result `tick` (one output,
// `tau`, all states) for the wrench [20, -10, 5, 1, 0.5, -0.2] at frame 0.
template <int NQ, int NV>
void ticks(FILE *results, const harness_states &states, const Dynamics<NQ, NV> &robot) {
    dyngen_array q{"q", NQ, 1}, qd{"qd", NV, 1}, qdd{"qdd", NV, 1}, tau{"tau", NV, 1};
    const double *positions = harness_input(&states, &q), *velocities = harness_input(&states, &qd);
    const double *accelerations = harness_input(&states, &qdd);
    Vector<6> wrench;
    wrench << 20, -10, 5, 1, 0.5, -0.2;
    Eigen::MatrixXd torques(NV, states.batch);
    for (size_t s = 0; s < states.batch; ++s) {
        torques.col(static_cast<Eigen::Index>(s)) =
            tick(robot, positions + s * NQ, velocities + s * NV, accelerations + s * NV, 0, wrench);
    }
    dyngen_function_info info{"tick", "tick", 0, nullptr, 1, &tau, 1, 1, DYNGEN_LOCAL_WORLD_ALIGNED};
    double *pointer = torques.data();
    harness_write_result(results, "tick", &states, &info, 0, &pointer);
}

}  // namespace

int main(int argc, char **argv) {
    if (argc < 3) {
        harness_fail("usage: check_cpp RESULTS STATES...");
    }
    FILE *results = std::fopen(argv[1], "w");
    if (results == nullptr) {
        harness_fail("cannot write %s", argv[1]);
    }
    for (int k = 2; k < argc; ++k) {
        harness_states states;
        harness_read_states(argv[k], &states);
        batches(results, states);
        std::string prefix = states.robot->prefix;
        if (prefix == "panda") {
            ticks(results, states, panda);
        } else if (prefix == "solo12") {
            ticks(results, states, solo12);
        }
    }
    std::fclose(results);
    std::puts("every batch evaluated, every tick consistent");
    return 0;
}

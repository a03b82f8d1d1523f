// The floating-base states of the dyngen benches (generated/benches/common/timing.rs,
// `floating_states`), drawn alike by the anchors of free-flyer robots so that both sides time
// the same states.
#pragma once

#include "timing.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace anchor {

struct FloatingState {
  Eigen::VectorXd q, v, a, tau;
};

// STATES states from the SplitMix64 stream of `seed`, per state: the configuration (base
// position and quaternion in ±1, the quaternion normalised, joints in ±π), then v in ±2, a in
// ±5 and τ in ±10.
inline std::vector<FloatingState> floating_states(int nq, int nv, uint64_t seed) {
  SplitMix64 rng{seed};
  const double pi = 3.14159265358979323846;
  auto draw = [&](int n, double bound) {
    Eigen::VectorXd x(n);
    for (int i = 0; i < n; ++i) x[i] = rng.uniform(-bound, bound);
    return x;
  };
  std::vector<FloatingState> out;
  for (int k = 0; k < STATES; ++k) {
    FloatingState s;
    s.q.resize(nq);
    for (int i = 0; i < nq; ++i) s.q[i] = rng.uniform(i < 7 ? -1.0 : -pi, i < 7 ? 1.0 : pi);
    s.q.segment<4>(3).normalize();
    s.v = draw(nv, 2.0);
    s.a = draw(nv, 5.0);
    s.tau = draw(nv, 10.0);
    out.push_back(s);
  }
  return out;
}

}  // namespace anchor

// Reads a Pinocchio model written as text by tools/anchors/frames/dump_model.py: every joint
// (type, parent, placement, inertia) and frame, each number exact. The anchors rebuild the
// model here (`addJoint`, `appendBodyToJoint`, `addFrame`) rather than with the wheel's URDF
// parser: that library is compiled for the default x86-64, and Eigen lays out fixed-size
// members differently under -march=native (AVX-512 alignment), so a Model built by the library
// and used by code compiled with -march=native crashes.
#pragma once

#include <pinocchio/multibody.hpp>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

namespace anchor {

// The joint types the text may hold: the revolute and prismatic axes, and the free flyer of a
// floating base.
template <typename JointModel>
inline pinocchio::JointIndex add_joint(pinocchio::Model &model, pinocchio::JointIndex parent,
                                       const pinocchio::SE3 &placement, const std::string &name) {
  return model.addJoint(parent, JointModel(), placement, name);
}

inline bool add_joint_of_type(pinocchio::Model &model, const std::string &type,
                              pinocchio::JointIndex parent, const pinocchio::SE3 &placement,
                              const std::string &name, pinocchio::JointIndex &id) {
  namespace pin = pinocchio;
  if (type == "JointModelRX") id = add_joint<pin::JointModelRX>(model, parent, placement, name);
  else if (type == "JointModelRY") id = add_joint<pin::JointModelRY>(model, parent, placement, name);
  else if (type == "JointModelRZ") id = add_joint<pin::JointModelRZ>(model, parent, placement, name);
  else if (type == "JointModelPX") id = add_joint<pin::JointModelPX>(model, parent, placement, name);
  else if (type == "JointModelPY") id = add_joint<pin::JointModelPY>(model, parent, placement, name);
  else if (type == "JointModelPZ") id = add_joint<pin::JointModelPZ>(model, parent, placement, name);
  else if (type == "JointModelFreeFlyer")
    id = add_joint<pin::JointModelFreeFlyer>(model, parent, placement, name);
  else return false;
  return true;
}

// `<models>/<name>.txt`; exits with a message naming the file when it cannot.
inline pinocchio::Model load_model(const std::string &models, const std::string &name) {
  namespace pin = pinocchio;
  const std::string path = models + "/" + name + ".txt";
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
  std::string tag, item;
  size_t joints = 0, frames = 0;
  in >> tag >> model.name >> joints >> frames;
  in >> tag;
  Eigen::Vector3d g;
  in >> g[0] >> g[1] >> g[2];
  model.gravity.linear(g);
  for (size_t k = 0; k < joints; ++k) {
    std::string type;
    pin::JointIndex parent;
    in >> tag >> item >> type >> parent;
    const pin::SE3 placement = read_se3();
    double mass;
    Eigen::Vector3d lever;
    Eigen::Matrix3d inertia;
    in >> mass >> lever[0] >> lever[1] >> lever[2];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) in >> inertia(i, j);
    pin::JointIndex id;
    if (!add_joint_of_type(model, type, parent, placement, item, id)) {
      std::fprintf(stderr, "%s: joint %s of type %s\n", path.c_str(), item.c_str(), type.c_str());
      std::exit(1);
    }
    model.appendBodyToJoint(id, pin::Inertia(mass, lever, inertia));
  }
  for (size_t k = 0; k < frames; ++k) {
    int type;
    pin::JointIndex parent_joint;
    pin::FrameIndex parent_frame;
    in >> tag >> item >> type >> parent_joint >> parent_frame;
    const pin::SE3 placement = read_se3();
    model.addFrame(pin::Frame(item, parent_joint, parent_frame, placement, (pin::FrameType)type),
                   false);
  }
  if (!in || (frames > 0 && tag != "frame")) {
    std::fprintf(stderr, "%s: malformed\n", path.c_str());
    std::exit(1);
  }
  return model;
}

// The BODY frame `name`; exits with a message when the model has none.
inline pinocchio::FrameIndex body_frame(const pinocchio::Model &model, const char *name) {
  if (!model.existFrame(name, pinocchio::BODY)) {
    std::fprintf(stderr, "%s: no body frame %s\n", model.name.c_str(), name);
    std::exit(1);
  }
  return model.getFrameId(name, pinocchio::BODY);
}

}  // namespace anchor

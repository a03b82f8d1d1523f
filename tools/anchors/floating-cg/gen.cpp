// Pinocchio 4.1's algorithms on a free-flyer robot, recorded as CppAD tapes of the scalar
// AD<CG<double>> and written out as plain C by CppADCodeGen: one file per (robot, function) and
// a table of them (functions.c, read through cg_functions.h). See README.md here.
//
//   gen MODELS_DIR OUT_DIR ROBOT...     (MODELS_DIR: build/models, the text models of
//                                        ../contacts/dump_model.py)
//
// The route is the one of Pinocchio's own CodeGenRNEA, CodeGenABA, … classes
// (pinocchio/codegen/cppadcg-algo.hpp): model.cast<AD<CG<double>>>(), a fresh Data,
// CppAD::Independent, the templated algorithm, ADFun::Dependent, ADFun::optimize
// ("no_compare_op"); then CppADCodeGen's CodeHandler with LanguageC and its default variable
// names, all its defaults. Each body is wrapped as `void <robot>_<function>(const double *x,
// double *y)`.
//
// Input x = [q (nq), v (nv), a or tau (nv)], the leading part a function reads: q is the
// configuration as Pinocchio takes it (base position, base quaternion x y z w normalised by the
// caller, joint angles), so each call computes the rotation of the quaternion and the joints'
// sines and cosines itself. Output y column-major; which it is: FUNCTIONS below.
//
// Prints one line per function: tape size, temporaries, C bytes, seconds from the recording to
// the written file; and per robot the totals.
#include <pinocchio/codegen/cppadcg.hpp>  // before the other Pinocchio headers

#include <pinocchio/algorithm/aba-derivatives.hpp>
#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/algorithm/centroidal.hpp>
#include <pinocchio/algorithm/crba.hpp>
#include <pinocchio/algorithm/rnea-derivatives.hpp>
#include <pinocchio/algorithm/rnea.hpp>

#include "../common/model_text.hpp"
#include "cg_functions.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace pin = pinocchio;
using CGD = CppAD::cg::CG<double>;
using ADS = CppAD::AD<CGD>;

// The functions, in the order of the table: name, inputs (CG_Q, CG_QV, CG_QVA, CG_QVTAU) and
// the output's shape (rows, columns) given nv.
struct Function {
  const char *name;
  int inputs;
  int rows_of_nv, cols_of_nv, rows_fixed;  // rows = rows_fixed ? rows_fixed : nv, cols = k nv or 1
};

const Function FUNCTIONS[] = {
    {"rnea", CG_QVA, 1, 0, 0},              // tau = rnea(q, v, a)                      nv
    {"crba", CG_Q, 1, 1, 0},                // M = crba(q), upper triangle mirrored     nv x nv
    {"coriolis", CG_QV, 1, 1, 0},           // C = computeCoriolisMatrix(q, v)          nv x nv
    {"gravity", CG_Q, 1, 0, 0},             // g = computeGeneralizedGravity(q)         nv
    {"aba", CG_QVTAU, 1, 0, 0},             // ddq = aba(q, v, tau), Convention::LOCAL  nv
    {"minv", CG_Q, 1, 1, 0},                // computeMinverse(q), upper mirrored       nv x nv
    {"rnea_derivatives", CG_QVA, 1, 2, 0},  // [dtau/dq, dtau/dv]                       nv x 2nv
    {"aba_derivatives", CG_QVTAU, 1, 2, 0}, // [dddq/dq, dddq/dv]                       nv x 2nv
    {"ccrba", CG_Q, 0, 1, 6},               // Ag = computeCentroidalMap(q)             6 x nv
};

int input_size(int inputs, int nq, int nv) { return inputs == CG_Q ? nq : inputs == CG_QV ? nq + nv : nq + 2 * nv; }
int rows(const Function &f, int nv) { return f.rows_fixed ? f.rows_fixed : nv; }
int cols(const Function &f, int nv) { return f.cols_of_nv ? f.cols_of_nv * nv : 1; }

template <typename Matrix>
Matrix mirrored_upper(Matrix m) {
  m.template triangularView<Eigen::StrictlyLower>() = m.transpose().template triangularView<Eigen::StrictlyLower>();
  return m;
}

// Function `f` of the AD model on x, flattened column-major.
Eigen::Matrix<ADS, Eigen::Dynamic, 1> record(const Function &f, const pin::ModelTpl<ADS> &m,
                                              pin::DataTpl<ADS> &d,
                                              const Eigen::Matrix<ADS, Eigen::Dynamic, 1> &x) {
  using Vector = Eigen::Matrix<ADS, Eigen::Dynamic, 1>;
  using Matrix = Eigen::Matrix<ADS, Eigen::Dynamic, Eigen::Dynamic>;
  const int nq = m.nq, nv = m.nv;
  const Vector q = x.head(nq);
  Vector v, a;  // a is tau for aba and aba_derivatives
  if (x.size() >= nq + nv) v = x.segment(nq, nv);
  if (x.size() == nq + 2 * nv) a = x.segment(nq + nv, nv);
  auto flat = [](const Matrix &M) { return Vector(Eigen::Map<const Vector>(M.data(), M.size())); };
  const std::string name = f.name;
  if (name == "rnea") return pin::rnea(m, d, q, v, a);
  if (name == "crba") return flat(mirrored_upper(Matrix(pin::crba(m, d, q))));
  if (name == "coriolis") return flat(pin::computeCoriolisMatrix(m, d, q, v));
  if (name == "gravity") return pin::computeGeneralizedGravity(m, d, q);
  if (name == "aba") return pin::aba(m, d, q, v, a);
  if (name == "minv") return flat(mirrored_upper(Matrix(pin::computeMinverse(m, d, q))));
  if (name == "rnea_derivatives" || name == "aba_derivatives") {
    // Zeroed outputs, as Pinocchio's CodeGenRNEADerivatives and CodeGenABADerivatives: the
    // algorithms write only the entries of supporting joints.
    Matrix dq = Matrix::Zero(nv, nv), dv = Matrix::Zero(nv, nv), da = Matrix::Zero(nv, nv);
    if (name == "rnea_derivatives") pin::computeRNEADerivatives(m, d, q, v, a, dq, dv, da);
    else pin::computeABADerivatives(m, d, q, v, a, dq, dv, da);
    Matrix y(nv, 2 * nv);
    y << dq, dv;
    return flat(y);
  }
  if (name == "ccrba") return flat(pin::computeCentroidalMap(m, d, q));
  std::fprintf(stderr, "gen: no function %s\n", f.name);
  std::exit(1);
}

struct Generated {
  size_t tape_ops = 0, temporaries = 0, bytes = 0;
  double seconds = 0;
};

// The point the tape is recorded at: any state does (the algorithms have no branch on the
// state); a unit quaternion, as every caller gives.
Eigen::VectorXd recording_point(int nq, int nv) {
  Eigen::VectorXd x(nq + 2 * nv);
  for (int i = 0; i < x.size(); ++i) x[i] = 0.3 + 0.5 * std::sin(1.3 * (i + 1));
  x.segment<4>(3).normalize();
  return x;
}

Generated generate(const pin::Model &model, const Function &f, const std::string &symbol,
                   const std::string &path) {
  Generated out;
  const auto start = std::chrono::steady_clock::now();
  using Vector = Eigen::Matrix<ADS, Eigen::Dynamic, 1>;
  const pin::ModelTpl<ADS> ad_model = model.cast<ADS>();
  pin::DataTpl<ADS> ad_data(ad_model);
  const Eigen::VectorXd x0 = recording_point(model.nq, model.nv);
  Vector x(input_size(f.inputs, model.nq, model.nv));
  for (int i = 0; i < x.size(); ++i) x[i] = ADS(x0[i]);
  CppAD::Independent(x);
  Vector y = record(f, ad_model, ad_data, x);
  CppAD::ADFun<CGD> tape;
  tape.Dependent(x, y);
  tape.optimize("no_compare_op");
  out.tape_ops = tape.size_op();

  CppAD::cg::CodeHandler<double> handler;
  std::vector<CGD> xs(tape.Domain());
  handler.makeVariables(xs);
  std::vector<CGD> ys = tape.Forward(0, xs);
  CppAD::cg::LanguageC<double> language("double");
  CppAD::cg::LangCDefaultVariableNameGenerator<double> names;
  std::ostringstream body;
  handler.generateCode(body, language, ys, names);
  const size_t low = names.getMinTemporaryVariableID(), high = names.getMaxTemporaryVariableID();
  out.temporaries = high + 1 > low ? high + 1 - low : 0;
  const std::string code = body.str();
  // The wrapper declares only v[]: CppADCodeGen's arrays (array[], sarray[]) would need more.
  if (code.find("array[") != std::string::npos) {
    std::fprintf(stderr, "gen: %s uses temporary arrays, which the wrapper does not declare\n",
                 symbol.c_str());
    std::exit(1);
  }
  std::ofstream file(path);
  file << "/* " << symbol << ": Pinocchio " << PINOCCHIO_VERSION
       << " through CppADCodeGen (tools/anchors/floating-cg/gen.cpp).\n"
       << " * x: " << tape.Domain() << " inputs, y: " << tape.Range()
       << " outputs (column-major); tape after optimize: " << out.tape_ops << " operations */\n"
       << "#include <math.h>\n\n"
       << "void " << symbol << "(const double *x, double *y) {\n";
  if (out.temporaries > 0) file << "   double v[" << out.temporaries << "];\n\n";
  file << code << "}\n";
  file.close();
  if (!file) {
    std::fprintf(stderr, "gen: cannot write %s\n", path.c_str());
    std::exit(1);
  }
  out.bytes = code.size();
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace

int main(int argc, char **argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: %s MODELS_DIR OUT_DIR ROBOT...\n", argv[0]);
    return 2;
  }
  const std::string models = argv[1], out_dir = argv[2];
  std::ostringstream declarations, tables, robots;
  std::printf("# %-7s %-17s %6s %7s %9s %8s %11s %8s\n", "robot", "function", "inputs", "outputs",
              "tape_ops", "temps", "C_bytes", "gen_s");
  for (int k = 3; k < argc; ++k) {
    const std::string robot = argv[k];
    const pin::Model model = anchor::load_model(models, robot);
    if (model.njoints < 2 || model.joints[1].shortname() != "JointModelFreeFlyer") {
      std::fprintf(stderr, "gen: %s/%s.txt: joint 1 is not a free flyer\n", models.c_str(),
                   robot.c_str());
      return 1;
    }
    size_t bytes = 0;
    double seconds = 0;
    tables << "static const CgFunction " << robot << "_functions[] = {\n";
    for (const Function &f : FUNCTIONS) {
      const std::string symbol = robot + "_" + f.name;
      const Generated g = generate(model, f, symbol, out_dir + "/" + symbol + ".c");
      const int r = rows(f, model.nv), c = cols(f, model.nv);
      std::printf("  %-7s %-17s %6d %7d %9zu %8zu %11zu %8.2f\n", robot.c_str(), f.name,
                  input_size(f.inputs, model.nq, model.nv), r * c, g.tape_ops, g.temporaries,
                  g.bytes, g.seconds);
      std::fflush(stdout);
      bytes += g.bytes;
      seconds += g.seconds;
      declarations << "void " << symbol << "(const double *x, double *y);\n";
      tables << "    {\"" << f.name << "\", " << symbol << ", " << f.inputs << ", " << r << ", " << c
             << "},\n";
    }
    tables << "};\n";
    robots << "    {\"" << robot << "\", " << model.nq << ", " << model.nv << ", "
           << sizeof(FUNCTIONS) / sizeof(FUNCTIONS[0]) << ", " << robot << "_functions},\n";
    std::printf("# %s: %zu bytes of C, %.1f s\n", robot.c_str(), bytes, seconds);
  }
  std::ofstream table(out_dir + "/functions.c");
  table << "/* The generated functions (tools/anchors/floating-cg/gen.cpp). */\n"
        << "#include \"cg_functions.h\"\n\n"
        << declarations.str() << "\n"
        << tables.str() << "\nstatic const CgRobot robots[] = {\n"
        << robots.str() << "};\n"
        << "const CgRobot *const cg_robots = robots;\n"
        << "const int cg_robot_count = " << argc - 3 << ";\n\n"
        << "/* The compiler's flags, given by build.sh. */\n"
        << "const char *const cg_flags = CG_FLAGS;\n";
  table.close();
  if (!table) {
    std::fprintf(stderr, "gen: cannot write %s/functions.c\n", out_dir.c_str());
    return 1;
  }
  return 0;
}

// The C library benchmark: each function of each robot library given on the command line,
// called from C++ through its exported C function (the shared library, loaded with dlopen),
// against the same function called from Rust (rust_side, linked in), and through P_evaluate on
// the whole batch (four states per call where the robot has lanes). Interleaved rounds over
// 256 random states; the median per state of each. Every call includes the sines and cosines of
// the state. benchmarks/c_library/run.sh builds and runs it.
//
// Usage: bench ROUNDS PREFIX=LIBRARY.so...
#include <dlfcn.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "dyngen.h"

extern "C" double dyngen_bench_rust(const char *robot, const char *function, size_t frame, size_t count,
                                    const double *const *inputs);

namespace {

constexpr size_t kStates = 256;
using Clock = std::chrono::steady_clock;

void fail(const std::string &message) {
    std::fprintf(stderr, "error: %s\n", message.c_str());
    std::exit(1);
}

// A library's symbol.
template <typename T>
T symbol(void *library, const std::string &name) {
    void *found = dlsym(library, name.c_str());
    if (found == nullptr) {
        fail("no symbol " + name);
    }
    return reinterpret_cast<T>(found);
}

// The inputs every function takes, by name: kStates states each.
struct States {
    std::vector<std::string> names{"q", "qd", "v", "a", "qdd", "tau", "parameters", "base_parameters", "r"};
    std::vector<std::vector<double>> values;

    States(size_t nq, size_t nv, size_t p, size_t b, bool floating) {
        std::mt19937_64 random(7);
        std::uniform_real_distribution<double> uniform(-2.0, 2.0);
        for (size_t length : {nq, nv, nv, nv, nv, nv, p, b, nv}) {
            std::vector<double> v(kStates * length);
            for (double &x : v) {
                x = uniform(random);
            }
            values.push_back(std::move(v));
        }
        if (floating) {
            for (size_t s = 0; s < kStates; ++s) {
                double *quaternion = values[0].data() + s * nq + 3, norm = 0;
                for (int i = 0; i < 4; ++i) norm += quaternion[i] * quaternion[i];
                for (int i = 0; i < 4; ++i) quaternion[i] /= std::sqrt(norm);
            }
        }
    }

    const double *input(const char *name) const {
        for (size_t k = 0; k < names.size(); ++k) {
            if (names[k] == name) return values[k].data();
        }
        fail(std::string("no input ") + name);
        return nullptr;
    }
};

// One pass of the exported function over every state, through a pointer of the function's
// arity (the frame, then N array pointers): nanoseconds per state.
template <size_t... I>
double direct(void *function, bool takes_frame, size_t frame, const std::vector<std::vector<double *>> &arguments,
              std::index_sequence<I...>) {
    auto start = Clock::now();
    if (takes_frame) {
        auto f = reinterpret_cast<int32_t (*)(size_t, decltype((void)I, (double *)nullptr)...)>(function);
        for (const auto &a : arguments) f(frame, a[I]...);
    } else {
        auto f = reinterpret_cast<int32_t (*)(decltype((void)I, (double *)nullptr)...)>(function);
        for (const auto &a : arguments) f(a[I]...);
    }
    return std::chrono::duration<double, std::nano>(Clock::now() - start).count() / arguments.size();
}

double direct(void *function, bool takes_frame, size_t frame, const std::vector<std::vector<double *>> &arguments) {
    switch (arguments.front().size()) {
        case 2: return direct(function, takes_frame, frame, arguments, std::make_index_sequence<2>{});
        case 3: return direct(function, takes_frame, frame, arguments, std::make_index_sequence<3>{});
        case 4: return direct(function, takes_frame, frame, arguments, std::make_index_sequence<4>{});
        case 5: return direct(function, takes_frame, frame, arguments, std::make_index_sequence<5>{});
        case 6: return direct(function, takes_frame, frame, arguments, std::make_index_sequence<6>{});
        case 7: return direct(function, takes_frame, frame, arguments, std::make_index_sequence<7>{});
        case 8: return direct(function, takes_frame, frame, arguments, std::make_index_sequence<8>{});
    }
    fail("a function of more than 8 arrays");
    return 0;
}

double median(std::vector<double> values) {
    std::sort(values.begin(), values.end());
    return values[values.size() / 2];
}

void bench(const std::string &prefix, const std::string &path, int rounds) {
    void *library = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (library == nullptr) {
        fail(dlerror());
    }
    auto get = [&](const char *name) { return symbol<size_t (*)(void)>(library, prefix + "_" + name)(); };
    auto info = symbol<const dyngen_function_info *(*)(size_t)>(library, prefix + "_function_info");
    auto evaluate = symbol<int32_t (*)(size_t, size_t, size_t, const double *const *, double *const *)>(
        library, prefix + "_evaluate");
    auto floating = symbol<int32_t (*)(void)>(library, prefix + "_is_floating_base")();
    States states(get("nq"), get("nv"), get("parameter_count"), get("base_parameter_count"), floating != 0);
    std::vector<const double *> rust_inputs;
    for (const auto &v : states.values) rust_inputs.push_back(v.data());
    // Frame functions of the last frame: not the end-effector, whose functions are the
    // kinematics' own.
    size_t frame = get("frame_count") - 1;
    std::printf("\n%s (%s), ns per state, median of %d rounds of %zu states\n", prefix.c_str(), path.c_str(), rounds,
                kStates);
    std::printf("%-44s %10s %10s %7s %12s\n", "function", "Rust", "C", "C/Rust", "C batch");
    for (size_t f = 0; f < get("function_count"); ++f) {
        const dyngen_function_info &fi = *info(f);
        std::vector<const double *> inputs;
        std::vector<std::vector<double>> outputs;
        std::vector<double *> output_pointers;
        for (size_t k = 0; k < fi.input_count; ++k) inputs.push_back(states.input(fi.inputs[k].name));
        for (size_t k = 0; k < fi.output_count; ++k) {
            outputs.emplace_back(kStates * fi.outputs[k].rows * fi.outputs[k].cols);
            output_pointers.push_back(outputs.back().data());
        }
        std::vector<std::vector<double *>> arguments(kStates);
        for (size_t s = 0; s < kStates; ++s) {
            for (size_t k = 0; k < fi.input_count; ++k)
                arguments[s].push_back(const_cast<double *>(inputs[k]) + s * fi.inputs[k].rows);
            for (size_t k = 0; k < fi.output_count; ++k)
                arguments[s].push_back(output_pointers[k] + s * fi.outputs[k].rows * fi.outputs[k].cols);
        }
        void *function = symbol<void *>(library, prefix + "_" + fi.name);
        std::vector<double> rust, c, batch;
        for (int round = 0; round < rounds; ++round) {
            rust.push_back(dyngen_bench_rust(prefix.c_str(), fi.name, frame, kStates, rust_inputs.data()));
            c.push_back(direct(function, fi.takes_frame != 0, frame, arguments));
            auto start = Clock::now();
            if (evaluate(f, frame, kStates, inputs.data(), output_pointers.data()) != DYNGEN_OK) {
                fail(prefix + "_evaluate " + fi.name + " failed");
            }
            batch.push_back(std::chrono::duration<double, std::nano>(Clock::now() - start).count() / kStates);
        }
        double r = median(rust), d = median(c);
        std::printf("%-44s %10.1f %10.1f %7.3f %12.1f%s\n", fi.name, r, d, d / r, median(batch),
                    fi.lanes > 1 ? " (lanes)" : "");
    }
}

}  // namespace

int main(int argc, char **argv) {
    if (argc < 3) {
        fail("usage: bench ROUNDS PREFIX=LIBRARY.so...");
    }
    int rounds = std::atoi(argv[1]);
    for (int k = 2; k < argc; ++k) {
        std::string arg = argv[k];
        size_t equals = arg.find('=');
        if (equals == std::string::npos) fail("not PREFIX=LIBRARY.so: " + arg);
        bench(arg.substr(0, equals), arg.substr(equals + 1), rounds);
    }
    return 0;
}

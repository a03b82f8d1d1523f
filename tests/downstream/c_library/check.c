/* The C11 program of tests/suite/c_library.rs: every function of every linked robot through
 * its own exported function, one state at a time, at the states the test wrote; its results
 * go to a file the test compares with the generic Rust dynamics. Around every call, a count
 * of the allocations (malloc and its kin, wrapped by the linker: -Wl,--wrap=malloc, …) must
 * stay at zero; then every status code is reached and each error must leave the outputs
 * untouched.
 *
 * Usage: check_c RESULTS STATES...   (exit status 0 when every check holds) */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"

/* ---- allocations, counted while `counting` is set */

static int counting;
static long allocations;
static long calls;

void *__real_malloc(size_t size);
void *__real_calloc(size_t count, size_t size);
void *__real_realloc(void *pointer, size_t size);
int __real_posix_memalign(void **pointer, size_t alignment, size_t size);
void *__real_aligned_alloc(size_t alignment, size_t size);

void *__wrap_malloc(size_t size) {
    allocations += counting;
    return __real_malloc(size);
}
void *__wrap_calloc(size_t count, size_t size) {
    allocations += counting;
    return __real_calloc(count, size);
}
void *__wrap_realloc(void *pointer, size_t size) {
    allocations += counting;
    return __real_realloc(pointer, size);
}
int __wrap_posix_memalign(void **pointer, size_t alignment, size_t size) {
    allocations += counting;
    return __real_posix_memalign(pointer, alignment, size);
}
void *__wrap_aligned_alloc(size_t alignment, size_t size) {
    allocations += counting;
    return __real_aligned_alloc(alignment, size);
}

/* A call of the library, counted. */
static int32_t counted(int32_t (*call)(size_t, size_t, const double *const *, double *const *), size_t function,
                       size_t frame, const double *const *inputs, double *const *outputs) {
    counting = 1;
    int32_t status = call(function, frame, inputs, outputs);
    counting = 0;
    ++calls;
    return status;
}

/* ---- status codes */

static int reached[DYNGEN_ERROR_NOT_GENERATED + 1];

static void expect(const harness_robot *robot, const char *what, int32_t status, int32_t expected) {
    if (status != expected) {
        harness_fail("%s: %s: status %d (%s), expected %d", robot->prefix, what, (int)status,
                     robot->status_message(status), (int)expected);
    }
    if (status >= 0 && status <= DYNGEN_ERROR_NOT_GENERATED) {
        reached[status] = 1;
    }
}

/* Fills `outputs` with a value no function writes, and checks that it is still there. */
static void fill(const dyngen_function_info *info, size_t batch, double **outputs, double value) {
    for (size_t k = 0; k < info->output_count; ++k) {
        for (size_t i = 0; i < batch * info->outputs[k].rows * info->outputs[k].cols; ++i) {
            outputs[k][i] = value;
        }
    }
}

static void untouched(const harness_robot *robot, const dyngen_function_info *info, size_t batch, double **outputs,
                      double value) {
    for (size_t k = 0; k < info->output_count; ++k) {
        for (size_t i = 0; i < batch * info->outputs[k].rows * info->outputs[k].cols; ++i) {
            if (outputs[k][i] != value) {
                harness_fail("%s: %s wrote output %s after an error", robot->prefix, info->name,
                             info->outputs[k].name);
            }
        }
    }
}

/* ---- every function, state by state, through its own symbol */

static void direct_calls(FILE *results, const harness_states *states) {
    const harness_robot *robot = states->robot;
    for (size_t f = 0; f < robot->function_count(); ++f) {
        const dyngen_function_info *info = robot->function_info(f);
        double *outputs[HARNESS_MAX_INPUTS];
        harness_outputs(states, info, outputs);
        for (size_t frame = 0; frame < harness_frames(robot, info); ++frame) {
            for (size_t s = 0; s < states->batch; ++s) {
                const double *in[HARNESS_MAX_INPUTS];
                double *out[HARNESS_MAX_INPUTS];
                for (size_t k = 0; k < info->input_count; ++k) {
                    in[k] = harness_input(states, &info->inputs[k]) + s * info->inputs[k].rows;
                }
                for (size_t k = 0; k < info->output_count; ++k) {
                    out[k] = outputs[k] + s * info->outputs[k].rows * info->outputs[k].cols;
                }
                expect(robot, info->name, counted(robot->call, f, frame, in, out), DYNGEN_OK);
            }
            harness_write_result(results, "direct", states, info, frame, outputs);
        }
        harness_free_outputs(info, outputs);
    }
}

/* ---- every error, through every function */

static void errors(const harness_states *states) {
    const harness_robot *robot = states->robot;
    size_t count = robot->function_count(), batch = states->batch;
    if (robot->function_info(count) != NULL) {
        harness_fail("%s: function_info(%zu) is not NULL", robot->prefix, count);
    }
    for (size_t f = 0; f < count; ++f) {
        const dyngen_function_info *info = robot->function_info(f);
        const double *in[HARNESS_MAX_INPUTS];
        double *outputs[HARNESS_MAX_INPUTS];
        harness_outputs(states, info, outputs);
        for (size_t k = 0; k < info->input_count; ++k) {
            in[k] = harness_input(states, &info->inputs[k]);
        }
        /* A null pointer: the first input, the last output, the arrays of P_evaluate. */
        const double *first = in[0];
        in[0] = NULL;
        expect(robot, info->name, counted(robot->call, f, 0, in, outputs), DYNGEN_ERROR_NULL_POINTER);
        expect(robot, info->name, robot->evaluate(f, 0, batch, in, outputs), DYNGEN_ERROR_NULL_POINTER);
        in[0] = first;
        double *last = outputs[info->output_count - 1];
        outputs[info->output_count - 1] = NULL;
        expect(robot, info->name, counted(robot->call, f, 0, in, outputs), DYNGEN_ERROR_NULL_POINTER);
        outputs[info->output_count - 1] = last;
        expect(robot, info->name, robot->evaluate(f, 0, batch, NULL, outputs), DYNGEN_ERROR_NULL_POINTER);
        expect(robot, info->name, robot->evaluate(f, 0, batch, in, NULL), DYNGEN_ERROR_NULL_POINTER);
        /* A frame beyond the last. */
        if (info->takes_frame) {
            size_t frame = robot->frame_count();
            fill(info, batch, outputs, 12345.0);
            expect(robot, info->name, counted(robot->call, f, frame, in, outputs), DYNGEN_ERROR_FRAME_OUT_OF_RANGE);
            expect(robot, info->name, robot->evaluate(f, frame, batch, in, outputs), DYNGEN_ERROR_FRAME_OUT_OF_RANGE);
            untouched(robot, info, batch, outputs, 12345.0);
        }
        /* A quaternion of norm 1.1, alone and as the third state of a batch. */
        if (robot->is_floating_base()) {
            size_t nq = info->inputs[0].rows;
            double *q = malloc(batch * nq * sizeof(double));
            memcpy(q, in[0], batch * nq * sizeof(double));
            for (size_t i = 3; i < 7; ++i) {
                q[2 * nq + i] *= 1.1;
            }
            in[0] = q + 2 * nq;
            fill(info, batch, outputs, 12345.0);
            expect(robot, info->name, counted(robot->call, f, 0, in, outputs), DYNGEN_ERROR_NON_UNIT_QUATERNION);
            in[0] = q;
            expect(robot, info->name, robot->evaluate(f, 0, batch, in, outputs), DYNGEN_ERROR_NON_UNIT_QUATERNION);
            untouched(robot, info, batch, outputs, 12345.0);
            free(q);
        }
        harness_free_outputs(info, outputs);
    }
    expect(robot, "evaluate beyond the table", robot->evaluate(count, 0, batch, NULL, NULL),
           DYNGEN_ERROR_FUNCTION_OUT_OF_RANGE);
    /* A null pointer, or a robot generated without base parameters (the test knows which). */
    double theta_b[1];
    int32_t status = robot->base_parameters(NULL, theta_b);
    expect(robot, "base_parameters", status,
           status == DYNGEN_ERROR_NOT_GENERATED ? DYNGEN_ERROR_NOT_GENERATED : DYNGEN_ERROR_NULL_POINTER);
    for (int32_t code = DYNGEN_OK; code <= DYNGEN_ERROR_NOT_GENERATED; ++code) {
        if (strcmp(robot->status_message(code), robot->status_message(-1)) == 0) {
            harness_fail("%s: status %d has no message of its own", robot->prefix, (int)code);
        }
    }
}

int main(int argc, char **argv) {
    if (argc < 3) {
        harness_fail("usage: check_c RESULTS STATES...");
    }
    /* The count sees an allocation. */
    counting = 1;
    free(malloc(16));
    counting = 0;
    if (allocations != 1) {
        harness_fail("the allocation count does not see malloc (%ld)", allocations);
    }
    allocations = 0;
    FILE *results = fopen(argv[1], "w");
    if (results == NULL) {
        harness_fail("cannot write %s", argv[1]);
    }
    for (int k = 2; k < argc; ++k) {
        harness_states states;
        harness_read_states(argv[k], &states);
        if (states.robot->abi_version() != DYNGEN_ABI_VERSION) {
            harness_fail("%s: ABI version %u, dyngen.h's %d", states.robot->prefix,
                         (unsigned)states.robot->abi_version(), DYNGEN_ABI_VERSION);
        }
        harness_write_metadata(results, states.robot);
        direct_calls(results, &states);
        errors(&states);
    }
    fclose(results);
    for (int32_t code = DYNGEN_OK; code <= DYNGEN_ERROR_NOT_GENERATED; ++code) {
        if (!reached[code]) {
            harness_fail("status %d was never returned", (int)code);
        }
    }
    printf("%ld calls, %ld allocations during them; every status code reached\n", calls, allocations);
    return allocations == 0 ? 0 : 1;
}

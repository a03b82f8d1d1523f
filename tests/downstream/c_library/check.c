/* The C11 program of tests/suite/c_library.rs: every function of every linked robot through
 * its own exported function, one state at a time, at the states the test wrote; its results
 * go to a file the test compares with the generic Rust dynamics; with an output over an input,
 * the same bits. Around every call, a count of the allocations (malloc and its kin, wrapped by
 * the linker: -Wl,--wrap=malloc, …) must stay at zero. The contact solves at every state, with
 * their statuses. Then every status code is reached and each error must leave the outputs
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

/* Another function's call, counted as `counted` counts. */
static int32_t last_status;
#define COUNTED(call) (counting = 1, last_status = (call), counting = 0, ++calls, last_status)

/* ---- status codes */

#define LAST_STATUS DYNGEN_ERROR_REDUNDANT_CONTACTS
static int reached[LAST_STATUS + 1];

static void expect(const harness_robot *robot, const char *what, int32_t status, int32_t expected) {
    if (status != expected) {
        harness_fail("%s: %s: status %d (%s), expected %d", robot->prefix, what, (int)status,
                     robot->status_message(status), (int)expected);
    }
    if (status >= 0 && status <= LAST_STATUS) {
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

/* ---- an output over an input of the same call: what separate arrays give, bit for bit */

static void overlapping(const harness_states *states) {
    const harness_robot *robot = states->robot;
    for (size_t f = 0; f < robot->function_count(); ++f) {
        const dyngen_function_info *info = robot->function_info(f);
        const double *in[HARNESS_MAX_INPUTS];
        double *separate[HARNESS_MAX_INPUTS], *out[HARNESS_MAX_INPUTS];
        for (size_t k = 0; k < info->input_count; ++k) {
            in[k] = harness_input(states, &info->inputs[k]);
        }
        harness_outputs(states, info, separate);
        expect(robot, info->name, counted(robot->call, f, 0, in, separate), DYNGEN_OK);
        /* Output j over input k, for every pair: the output as long as the input or shorter
         * lies at its start, a longer one starts with it. */
        for (size_t j = 0; j < info->output_count; ++j) {
            size_t length = info->outputs[j].rows * info->outputs[j].cols;
            for (size_t k = 0; k < info->input_count; ++k) {
                size_t rows = info->inputs[k].rows;
                double *shared = malloc((rows > length ? rows : length) * sizeof(double));
                memcpy(shared, in[k], rows * sizeof(double));
                const double *input = in[k];
                in[k] = shared;
                harness_outputs(states, info, out);
                double *own = out[j];
                out[j] = shared;
                expect(robot, info->name, counted(robot->call, f, 0, in, out), DYNGEN_OK);
                out[j] = own;
                in[k] = input;
                for (size_t o = 0; o < info->output_count; ++o) {
                    const double *got = o == j ? shared : out[o];
                    size_t size = info->outputs[o].rows * info->outputs[o].cols * sizeof(double);
                    if (memcmp(got, separate[o], size) != 0) {
                        harness_fail("%s: %s: output %s over input %s changes output %s", robot->prefix, info->name,
                                     info->outputs[j].name, info->inputs[k].name, info->outputs[o].name);
                    }
                }
                harness_free_outputs(info, out);
                free(shared);
            }
        }
        harness_free_outputs(info, separate);
    }
}

/* ---- contacts: the three solves at every state, written with their statuses for the test to
 * compare with the generic dynamics (a robot without contacts refuses them); then each error */

enum { MU, MAX_ITERATIONS, ACCURACY, KP, KD, RESTITUTION, DAMPING, SETTINGS };

/* The contacts held to the world: the anchors of a stabilised solve. */
static size_t anchor_count(const harness_robot *robot) {
    size_t count = 0;
    for (size_t k = 0; k < robot->contact_count(); ++k) {
        count += robot->contact_info(k)->to == DYNGEN_HELD_TO_WORLD;
    }
    return count;
}

static dyngen_contact_settings settings_of(const double *c, const double *anchors) {
    dyngen_contact_settings settings = {c[MU], (size_t)c[MAX_ITERATIONS], c[ACCURACY], c[KP], c[KD], anchors};
    return settings;
}

/* `count` doubles (at least one, so that no pointer is NULL), each `value`. */
static double *filled(size_t count, double value) {
    double *values = malloc((count > 0 ? count : 1) * sizeof(double));
    for (size_t i = 0; i < count; ++i) {
        values[i] = value;
    }
    return values;
}

static void untouched_values(const harness_robot *robot, const char *what, const double *values, size_t count,
                             double value) {
    for (size_t i = 0; i < count; ++i) {
        if (values[i] != value) {
            harness_fail("%s: %s wrote an output after an error", robot->prefix, what);
        }
    }
}

/* One solve's result: a status per state, then its outputs. */
static void write_solve(FILE *results, const harness_states *states, const char *name, const double *status,
                        size_t output_count, const char *const *names, const size_t *lengths,
                        double *const *outputs) {
    fprintf(results, "result contacts %s %s 0\n", states->robot->prefix, name);
    harness_write_values(results, "status", states->batch, status);
    for (size_t k = 0; k < output_count; ++k) {
        harness_write_values(results, names[k], states->batch * lengths[k], outputs[k]);
    }
    fprintf(results, "end\n");
}

static void contact_solves(FILE *results, const harness_states *states) {
    const harness_robot *robot = states->robot;
    size_t nq = robot->nq(), nv = robot->nv(), nc = robot->nc(), batch = states->batch;
    size_t anchors_length = 12 * anchor_count(robot);
    const double *q = harness_named(states, "q", nq), *qd = harness_named(states, "qd", nv);
    const double *tau = harness_named(states, "tau", nv);
    const double *anchors = harness_named(states, "anchors", anchors_length);
    const double *settings = harness_named(states, "contact_settings", SETTINGS);
    double *status[4], *qdd = filled(batch * nv, NAN), *forces = filled(batch * nc, NAN);
    double *qdd_stabilised = filled(batch * nv, NAN), *forces_stabilised = filled(batch * nc, 0.0);
    double *qd_after = filled(batch * nv, NAN), *impulses = filled(batch * nc, NAN);
    double *inertia = filled(batch * nc * nc, NAN);
    for (size_t k = 0; k < 4; ++k) {
        status[k] = filled(batch, NAN);
    }
    for (size_t s = 0; s < batch; ++s) {
        const double *qs = q + s * nq, *qds = qd + s * nv, *taus = tau + s * nv, *c = settings + s * SETTINGS;
        dyngen_contact_settings stabilised = settings_of(c, anchors + s * anchors_length);
        int32_t got[4];
        got[0] = COUNTED(robot->constrained_forward_dynamics(qs, qds, taus, NULL, NULL, qdd + s * nv, forces + s * nc));
        /* Warm-started from zero forces and written over them: what no warm start gives. */
        double *warm = forces_stabilised + s * nc;
        got[1] = COUNTED(robot->constrained_forward_dynamics(qs, qds, taus, &stabilised, warm, qdd_stabilised + s * nv,
                                                             warm));
        got[2] = COUNTED(robot->impulse_dynamics(qs, qds, c[RESTITUTION], c[MU], qd_after + s * nv, impulses + s * nc));
        got[3] = COUNTED(robot->operational_space_inertia(qs, c[DAMPING], inertia + s * nc * nc));
        for (size_t k = 0; k < 4; ++k) {
            status[k][s] = got[k];
            if (got[k] >= 0 && got[k] <= LAST_STATUS) {
                reached[got[k]] = 1;
            }
        }
    }
    const char *pair[] = {"qdd", "forces"}, *impact[] = {"qd_after", "impulses"}, *osi[] = {"inertia"};
    size_t pair_lengths[] = {nv, nc}, osi_lengths[] = {nc * nc};
    double *exact[] = {qdd, forces}, *stable[] = {qdd_stabilised, forces_stabilised};
    double *impulse[] = {qd_after, impulses};
    write_solve(results, states, "constrained_forward_dynamics", status[0], 2, pair, pair_lengths, exact);
    write_solve(results, states, "constrained_forward_dynamics_stabilised", status[1], 2, pair, pair_lengths, stable);
    write_solve(results, states, "impulse_dynamics", status[2], 2, impact, pair_lengths, impulse);
    write_solve(results, states, "operational_space_inertia", status[3], 1, osi, osi_lengths, &inertia);
    double *all[] = {qdd, forces, qdd_stabilised, forces_stabilised, qd_after, impulses, inertia};
    for (size_t k = 0; k < sizeof all / sizeof all[0]; ++k) {
        free(all[k]);
    }
    for (size_t k = 0; k < 4; ++k) {
        free(status[k]);
    }
}

static void contact_errors(const harness_states *states) {
    const harness_robot *robot = states->robot;
    size_t nq = robot->nq(), nv = robot->nv(), nc = robot->nc();
    if (nc == 0) {
        return; /* DYNGEN_ERROR_NOT_GENERATED, in the results */
    }
    const double *q = harness_named(states, "q", nq), *qd = harness_named(states, "qd", nv);
    const double *tau = harness_named(states, "tau", nv);
    const double *c = harness_named(states, "contact_settings", SETTINGS);
    const double *anchors = harness_named(states, "anchors", 12 * anchor_count(robot));
    double *qdd = filled(nv, 12345.0), *forces = filled(nc, 12345.0), *inertia = filled(nc * nc, 12345.0);
    const char *forward = "constrained_forward_dynamics", *impulse = "impulse_dynamics";
    const char *osi = "operational_space_inertia";
    /* A null pointer: an input, an output; the anchors of a stabilised solve. */
    expect(robot, forward, COUNTED(robot->constrained_forward_dynamics(NULL, qd, tau, NULL, NULL, qdd, forces)),
           DYNGEN_ERROR_NULL_POINTER);
    expect(robot, forward, COUNTED(robot->constrained_forward_dynamics(q, qd, tau, NULL, NULL, qdd, NULL)),
           DYNGEN_ERROR_NULL_POINTER);
    dyngen_contact_settings settings = settings_of(c, NULL);
    if (anchor_count(robot) > 0) {
        expect(robot, forward, COUNTED(robot->constrained_forward_dynamics(q, qd, tau, &settings, NULL, qdd, forces)),
               DYNGEN_ERROR_NULL_POINTER);
    }
    expect(robot, impulse, COUNTED(robot->impulse_dynamics(q, NULL, 0.0, 0.0, qdd, forces)), DYNGEN_ERROR_NULL_POINTER);
    expect(robot, osi, COUNTED(robot->operational_space_inertia(q, 0.0, NULL)), DYNGEN_ERROR_NULL_POINTER);
    /* Settings out of range: mu negative or NaN, no iteration, an infinite gain; a restitution
     * outside [0, 1]; a negative damping. */
    settings.anchors = anchors;
    double bad_mu[] = {-1.0, NAN};
    for (size_t k = 0; k < 2; ++k) {
        settings.mu = bad_mu[k];
        expect(robot, forward, COUNTED(robot->constrained_forward_dynamics(q, qd, tau, &settings, NULL, qdd, forces)),
               DYNGEN_ERROR_CONTACT_SETTINGS);
        expect(robot, impulse, COUNTED(robot->impulse_dynamics(q, qd, 0.5, bad_mu[k], qdd, forces)),
               DYNGEN_ERROR_CONTACT_SETTINGS);
    }
    settings = settings_of(c, anchors);
    settings.max_iterations = 0;
    expect(robot, forward, COUNTED(robot->constrained_forward_dynamics(q, qd, tau, &settings, NULL, qdd, forces)),
           DYNGEN_ERROR_CONTACT_SETTINGS);
    settings = settings_of(c, anchors);
    settings.kd = INFINITY;
    expect(robot, forward, COUNTED(robot->constrained_forward_dynamics(q, qd, tau, &settings, NULL, qdd, forces)),
           DYNGEN_ERROR_CONTACT_SETTINGS);
    expect(robot, impulse, COUNTED(robot->impulse_dynamics(q, qd, 1.5, c[MU], qdd, forces)),
           DYNGEN_ERROR_CONTACT_SETTINGS);
    expect(robot, osi, COUNTED(robot->operational_space_inertia(q, -1.0, inertia)), DYNGEN_ERROR_CONTACT_SETTINGS);
    /* A quaternion of norm 1.1. */
    if (robot->is_floating_base()) {
        double *bad = filled(nq, 0.0);
        memcpy(bad, q, nq * sizeof(double));
        for (size_t i = 3; i < 7; ++i) {
            bad[i] *= 1.1;
        }
        expect(robot, forward, COUNTED(robot->constrained_forward_dynamics(bad, qd, tau, NULL, NULL, qdd, forces)),
               DYNGEN_ERROR_NON_UNIT_QUATERNION);
        expect(robot, impulse, COUNTED(robot->impulse_dynamics(bad, qd, 0.5, c[MU], qdd, forces)),
               DYNGEN_ERROR_NON_UNIT_QUATERNION);
        expect(robot, osi, COUNTED(robot->operational_space_inertia(bad, c[DAMPING], inertia)),
               DYNGEN_ERROR_NON_UNIT_QUATERNION);
        free(bad);
    }
    untouched_values(robot, "a contact solve", qdd, nv, 12345.0);
    untouched_values(robot, "a contact solve", forces, nc, 12345.0);
    untouched_values(robot, "a contact solve", inertia, nc * nc, 12345.0);
    free(qdd);
    free(forces);
    free(inertia);
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
    for (int32_t code = DYNGEN_OK; code <= LAST_STATUS; ++code) {
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
        overlapping(&states);
        contact_solves(results, &states);
        errors(&states);
        contact_errors(&states);
    }
    fclose(results);
    for (int32_t code = DYNGEN_OK; code <= LAST_STATUS; ++code) {
        if (!reached[code]) {
            harness_fail("status %d was never returned", (int)code);
        }
    }
    printf("%ld calls, %ld allocations during them; every status code reached\n", calls, allocations);
    return allocations == 0 ? 0 : 1;
}

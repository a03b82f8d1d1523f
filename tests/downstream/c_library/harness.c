/* The harness of the C and C++ test programs: see harness.h. */
#include "harness.h"

#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

void harness_fail(const char *format, ...) {
    va_list args;
    va_start(args, format);
    fprintf(stderr, "error: ");
    vfprintf(stderr, format, args);
    fprintf(stderr, "\n");
    va_end(args);
    exit(1);
}

static const harness_robot *find_robot(const char *prefix) {
    for (size_t k = 0; k < harness_robot_count; ++k) {
        if (strcmp(harness_robots[k].prefix, prefix) == 0) {
            return &harness_robots[k];
        }
    }
    harness_fail("no robot library with the prefix %s is linked", prefix);
    return NULL;
}

void harness_read_states(const char *path, harness_states *states) {
    FILE *file = fopen(path, "r");
    char prefix[64];
    if (file == NULL || fscanf(file, "robot %63s %zu", prefix, &states->batch) != 2) {
        harness_fail("%s: not a states file", path);
    }
    states->robot = find_robot(prefix);
    states->count = 0;
    char name[32];
    size_t count;
    while (fscanf(file, "%31s %zu", name, &count) == 2) {
        size_t k = states->count++;
        if (k == HARNESS_MAX_INPUTS || count % states->batch != 0) {
            harness_fail("%s: input %s: too many inputs, or not %zu states", path, name, states->batch);
        }
        strcpy(states->names[k], name);
        states->lengths[k] = count / states->batch;
        states->values[k] = malloc(count * sizeof(double));
        for (size_t i = 0; i < count; ++i) {
            if (fscanf(file, "%lf", &states->values[k][i]) != 1) {
                harness_fail("%s: input %s: %zu numbers expected", path, name, count);
            }
        }
    }
    fclose(file);
}

const double *harness_input(const harness_states *states, const dyngen_array *array) {
    for (size_t k = 0; k < states->count; ++k) {
        if (strcmp(states->names[k], array->name) == 0) {
            if (states->lengths[k] != array->rows || array->cols != 1) {
                harness_fail("%s: input %s has %zu x %zu entries, the states %zu", states->robot->prefix,
                             array->name, array->rows, array->cols, states->lengths[k]);
            }
            return states->values[k];
        }
    }
    harness_fail("%s: no states of the input %s", states->robot->prefix, array->name);
    return NULL;
}

void harness_outputs(const harness_states *states, const dyngen_function_info *info, double **outputs) {
    for (size_t k = 0; k < info->output_count; ++k) {
        size_t count = states->batch * info->outputs[k].rows * info->outputs[k].cols;
        outputs[k] = malloc(count * sizeof(double));
        for (size_t i = 0; i < count; ++i) {
            outputs[k][i] = NAN;
        }
    }
}

void harness_free_outputs(const dyngen_function_info *info, double **outputs) {
    for (size_t k = 0; k < info->output_count; ++k) {
        free(outputs[k]);
    }
}

static void write_values(FILE *file, const char *name, size_t count, const double *values) {
    fprintf(file, "%s %zu", name, count);
    for (size_t i = 0; i < count; ++i) {
        fprintf(file, " %.17g", values[i]);
    }
    fprintf(file, "\n");
}

void harness_write_result(FILE *file, const char *how, const harness_states *states,
                          const dyngen_function_info *info, size_t frame, double *const *outputs) {
    fprintf(file, "result %s %s %s %zu\n", how, states->robot->prefix, info->name, frame);
    for (size_t k = 0; k < info->output_count; ++k) {
        const dyngen_array *array = &info->outputs[k];
        write_values(file, array->name, states->batch * array->rows * array->cols, outputs[k]);
    }
    fprintf(file, "end\n");
}

static void write_names(FILE *file, const char *what, size_t count, const char *(*name)(size_t)) {
    for (size_t i = 0; i < count; ++i) {
        fprintf(file, "%s %zu %s\n", what, i, name(i));
    }
    if (name(count) != NULL) {
        harness_fail("%s %zu exists, beyond the count", what, count);
    }
}

void harness_write_metadata(FILE *file, const harness_robot *robot) {
    size_t dof = robot->dof(), p = robot->parameter_count(), b = robot->base_parameter_count();
    fprintf(file, "metadata %s\nrobot_name %s\n", robot->prefix, robot->robot_name());
    fprintf(file, "abi_version %u\nis_floating_base %d\n", (unsigned)robot->abi_version(), (int)robot->is_floating_base());
    fprintf(file, "sizes %zu %zu %zu %zu %zu %zu %zu\n", dof, robot->nq(), robot->nv(), p, b, robot->frame_count(),
            robot->function_count());
    write_names(file, "joint_name", dof, robot->joint_name);
    write_names(file, "parameter_name", p, robot->parameter_name);
    write_names(file, "base_parameter_name", b, robot->base_parameter_name);
    write_names(file, "frame_name", robot->frame_count(), robot->frame_name);
    double *theta = malloc(p * sizeof(double)), *theta_b = malloc((b + 1) * sizeof(double));
    double *limits = malloc(4 * dof * sizeof(double));
    if (robot->parameters(theta) != DYNGEN_OK ||
        robot->joint_limits(limits, limits + dof, limits + 2 * dof, limits + 3 * dof) != DYNGEN_OK) {
        harness_fail("%s: parameters or joint limits failed", robot->prefix);
    }
    write_values(file, "parameters", p, theta);
    if (robot->base_parameters(theta, theta_b) == DYNGEN_OK) {
        write_values(file, "base_parameters", b, theta_b);
    }
    write_values(file, "joint_limits", 4 * dof, limits);
    fprintf(file, "end\n");
    free(theta);
    free(theta_b);
    free(limits);
}

size_t harness_frames(const harness_robot *robot, const dyngen_function_info *info) {
    return info->takes_frame ? robot->frame_count() : 1;
}

/* What the C and C++ test programs of tests/suite/c_library.rs share: the robots they are
 * linked with (a registry the test generates from the robots' headers, calls.c), the states
 * the test writes for them, and the results they write back for the test to compare with the
 * generic Rust dynamics. */
#ifndef HARNESS_H
#define HARNESS_H

#include <stdio.h>

#include "dyngen.h"

#ifdef __cplusplus
extern "C" {
#endif

/* One robot library, through its symbols (calls.c). */
typedef struct harness_robot {
    const char *prefix;
    uint32_t (*abi_version)(void);
    const char *(*robot_name)(void);
    int32_t (*is_floating_base)(void);
    size_t (*dof)(void);
    size_t (*nq)(void);
    size_t (*nv)(void);
    size_t (*parameter_count)(void);
    size_t (*base_parameter_count)(void);
    size_t (*frame_count)(void);
    size_t (*function_count)(void);
    const char *(*joint_name)(size_t);
    const char *(*parameter_name)(size_t);
    const char *(*base_parameter_name)(size_t);
    const char *(*frame_name)(size_t);
    const char *(*status_message)(int32_t);
    int32_t (*parameters)(double *);
    int32_t (*base_parameters)(const double *, double *);
    int32_t (*joint_limits)(double *, double *, double *, double *);
    const dyngen_function_info *(*function_info)(size_t);
    int32_t (*evaluate)(size_t, size_t, size_t, const double *const *, double *const *);
    /* Entry `function` through its own exported function, one state. */
    int32_t (*call)(size_t function, size_t frame, const double *const *inputs, double *const *outputs);
} harness_robot;

extern const harness_robot harness_robots[];
extern const size_t harness_robot_count;

#define HARNESS_MAX_INPUTS 16

/* One robot's states: named inputs, `batch` states of each, state after state. */
typedef struct harness_states {
    const harness_robot *robot;
    size_t batch;
    size_t count;
    char names[HARNESS_MAX_INPUTS][32];
    size_t lengths[HARNESS_MAX_INPUTS];
    double *values[HARNESS_MAX_INPUTS];
} harness_states;

/* Prints the message and exits with status 1. */
void harness_fail(const char *format, ...);
/* Reads a states file (`robot <prefix> <batch>`, then `<name> <count> <values>` lines). */
void harness_read_states(const char *path, harness_states *states);
/* The input an entry's array names, `batch` states of it; fails if absent or of another length. */
const double *harness_input(const harness_states *states, const dyngen_array *array);
/* `batch` states of each output of `info`, filled with NaN (free with harness_free_outputs). */
void harness_outputs(const harness_states *states, const dyngen_function_info *info, double **outputs);
void harness_free_outputs(const dyngen_function_info *info, double **outputs);
/* Writes `result <how> <prefix> <function> <frame>` and one line per output. */
void harness_write_result(FILE *file, const char *how, const harness_states *states,
                          const dyngen_function_info *info, size_t frame, double *const *outputs);
/* Writes the robot's sizes, names, parameters and limits (`metadata <prefix>` … `end`). */
void harness_write_metadata(FILE *file, const harness_robot *robot);
/* The number of frames entry `info` is evaluated for: the robot's frames, or 1. */
size_t harness_frames(const harness_robot *robot, const dyngen_function_info *info);

#ifdef __cplusplus
}
#endif

#endif

/* The table of the C functions gen.cpp writes (functions.c), read by bench_floating_cg.cpp. */
#ifndef CG_FUNCTIONS_H
#define CG_FUNCTIONS_H

#ifdef __cplusplus
extern "C" {
#endif

/* What a function reads: the leading part of x = [q (nq), v (nv), a or tau (nv)]. */
enum { CG_Q = 1, CG_QV = 2, CG_QVA = 3, CG_QVTAU = 4 };

/* x: at least as many doubles as `inputs` says, q's quaternion of norm 1; y: rows x cols,
 * column-major, every entry written. */
typedef void (*CgCall)(const double *x, double *y);

typedef struct {
  const char *name; /* as the numeric rows name the Pinocchio call: rnea, crba, ... */
  CgCall call;
  int inputs;
  int rows, cols;
} CgFunction;

typedef struct {
  const char *name;
  int nq, nv;
  int function_count;
  const CgFunction *functions;
} CgRobot;

extern const CgRobot *const cg_robots;
extern const int cg_robot_count;
/* How the generated C was compiled (functions.c is compiled with -DCG_FLAGS="\"...\""). */
extern const char *const cg_flags;

#ifdef __cplusplus
}
#endif

#endif

/* The C ABI of a model kernel (docs/command-line.md, *Kernels*): what `phynjo-lagc
 * --emit=kernel` compiles into a shared object, and what the runtime loads (kernel.hpp).
 *
 * One entry point, `phynjo_kernel_v1`, returns a table: the model's sizes and names, its
 * parameters as an opaque object (made, copied, read and set by index), and its functions.
 * Arrays are plain doubles in the layouts of docs/generated-code.md (M: dof×dof row-major,
 * …). A function returns PHYNJO_OK or an error kind, the message then in last_error() (this
 * thread's); the predicates (accelerations_energy_guards, rk4_step_values, …) return 1 or 0, or
 * −status when they throw.
 * A caller passes arrays of the right lengths: the kernel does not check them. */
#ifndef PHYNJO_RUNTIME_SYSTEM_KERNEL_ABI_H
#define PHYNJO_RUNTIME_SYSTEM_KERNEL_ABI_H

#include <stddef.h>

/* Raised when the table changes in a way an older loader cannot read. */
#define PHYNJO_KERNEL_ABI_VERSION 4u
#define PHYNJO_KERNEL_ENTRY "phynjo_kernel_v1"

#ifdef __cplusplus
extern "C" {
#endif

enum phynjo_status {
    PHYNJO_OK = 0,
    PHYNJO_SINGULAR_MASS_MATRIX = 1, /* phynjo::runtime::SingularMassMatrix */
    PHYNJO_SINGULAR_CONSTRAINTS = 2, /* phynjo::runtime::SingularConstraints */
    PHYNJO_NON_FINITE = 3,           /* phynjo::runtime::NonFiniteResult */
    PHYNJO_INVALID_ARGUMENT = 4,     /* std::invalid_argument */
    PHYNJO_OUT_OF_RANGE = 5,         /* std::out_of_range */
    PHYNJO_ERROR = 9                 /* anything else */
};

/* f(P, t, q, q', out) and f(P, t, q, out): the shapes of most model functions. */
typedef int (*phynjo_state_fn)(const void* P, double t, const double* q, const double* qdot, double* out);
typedef int (*phynjo_positions_fn)(const void* P, double t, const double* q, double* out);

typedef struct phynjo_kernel {
    unsigned abi_version; /* PHYNJO_KERNEL_ABI_VERSION */
    size_t table_size;    /* sizeof(phynjo_kernel) where the kernel was compiled */
    const char* model_name;
    const char* phynjo_version; /* of the phynjo-lagc that wrote the kernel */

    size_t dof, n_parameters, n_inputs, n_constraints, n_events, n_shapes, n_spheres, n_capsules, n_boxes,
        n_shape_values, lane_width;
    int mass_depends_on_velocities;
    const char* const* coordinate_names; /* dof */
    const char* const* parameter_names;  /* n_parameters: every field of Parameters, inputs among them */
    const char* const* parameter_units;  /* n_parameters: "" when none */
    const double* parameter_defaults;    /* n_parameters: the file's values */
    const unsigned char* parameter_is_input;   /* n_parameters */
    const unsigned char* parameter_is_derived; /* n_parameters: defined from others (it follows them) */
    const char* const* constraint_names;       /* n_constraints */
    const unsigned char* constraint_holonomic; /* n_constraints */
    const char* const* event_names;            /* n_events */
    const int* event_directions;               /* n_events: -1 falling, +1 rising */
    const unsigned char* event_stops;          /* n_events */
    const char* const* shape_names;            /* n_shapes */
    const unsigned char* shape_kinds;          /* n_shapes: 0 segment, 1 sphere, 2 capsule, 3 box */

    /* Parameters: an opaque object at the file's defaults; set fixes a value (a derived one
     * stops following); get reads the value set, or the file's default. */
    void* (*parameters_new)(void);
    void* (*parameters_copy)(const void* P);
    void (*parameters_delete)(void* P);
    void (*parameters_set)(void* P, size_t k, double value);
    double (*parameters_get)(const void* P, size_t k);
    /* An address naming the Parameters type (a byte of the kernel's): runs of one kernel share lanes. */
    const void* (*parameters_type)(void);

    phynjo_state_fn mass_matrix; /* q' unused unless mass_depends_on_velocities */
    phynjo_state_fn forcing, accelerations, momenta, generalized_forces;
    phynjo_state_fn constraint_residuals, constraint_velocity_residuals, constraint_scales, constraint_gamma;
    phynjo_state_fn rhs_jacobian, input_jacobian, event_guards;
    phynjo_positions_fn constraint_matrix, shape_positions, sphere_jacobians, capsule_jacobians, box_jacobians;
    int (*energy)(const void* P, double t, const double* q, const double* qdot, double* E);
    int (*accelerations_and_multipliers)(const void* P, double t, const double* q, const double* qdot, double* qddot,
                                         double* lambda);
    int (*canonical_jacobian)(const void* P, double t, const double* q, const double* qdot, double* p, double* F,
                              double* dp, double* dF);
    int (*rk4_step)(const void* P, double t, double h, double* q, double* qdot, const double* qddot);
    int (*accelerations_energy_guards)(const void* P, double t, const double* q, const double* qdot, double* qddot,
                                       double* E, double* g); /* 1, 0 or -status */
    int (*rk4_step_values)(const void* P, double t, double h, double t1, double* q, double* qdot, double* qddot,
                           double* E, double* g); /* 1, 0 or -status */
    int (*rk4_step_values_lanes_each)(const void* const* P, const double* t, const double* h, const double* t1,
                                      double* q, double* qdot, double* qddot, double* E, double* g); /* null: none */
    int (*initial_state)(const void* P, double* q, double* qdot);
    int (*apply_event)(const void* P, size_t k, double t, double* q, double* qdot);
    int (*sphere_radii)(const void* P, double* r);
    int (*capsule_radii)(const void* P, double* r);
    int (*box_half_extents)(const void* P, double* h); /* 3 n_boxes */
    const char* (*last_error)(void);
} phynjo_kernel;

typedef const phynjo_kernel* (*phynjo_kernel_entry)(void);

#ifdef __cplusplus
}
#endif

#endif

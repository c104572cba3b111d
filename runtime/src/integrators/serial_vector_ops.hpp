#pragma once
// Faster serial-vector operations for the SUNDIALS solvers. Internal to the runtime (cvode.cpp,
// ida.cpp); see serial_vector_ops.cpp.
#include <sundials/sundials_nvector.h>

namespace phynjo::runtime::sundials {

/// Replaces the hottest operations of a serial N_Vector — N_VLinearSum and N_VWrmsNorm — by
/// ours; every vector the solver clones from `v` inherits them. SUNDIALS' own serial vector
/// (as Debian builds it: generic x86-64, one accumulator) spends most of a small system's
/// step in them.
///  * linear_sum: SUNDIALS' case analysis and arithmetic exactly (z = x + y, x − y, c·x ± y,
///    c·(x ± y), a·x + b·y; axpy in place), so the same bits (the file is compiled without
///    floating-point contraction, as SUNDIALS is), in loops the compiler vectorizes.
///  * wrms_norm: √(Σ(xᵢwᵢ)²/n) with four partial sums (fixed order: deterministic, within a
///    few ulps of the one-accumulator sum), so the additions need not wait on each other.
void use_fast_serial_ops(N_Vector v);

/// The operations themselves (tested against SUNDIALS' serial ones).
void linear_sum(double a, N_Vector x, double b, N_Vector y, N_Vector z);
double wrms_norm(N_Vector x, N_Vector w);

} // namespace phynjo::runtime::sundials

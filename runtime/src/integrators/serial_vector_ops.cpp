// Serial N_Vector operations for CVODE and IDA. See serial_vector_ops.hpp. Compiled with
// -ffp-contract=off (runtime/CMakeLists.txt): a·x + b·y rounds twice, as in SUNDIALS.
#include "serial_vector_ops.hpp"

#include <nvector/nvector_serial.h>

#include <cmath>

namespace phynjo::runtime::sundials {

namespace {

// z = c·x + y and friends over n entries; x, y, z may be the same array (elementwise).
void lin1(long n, double c, const double* x, const double* y, double* z) {
    for (long i = 0; i < n; ++i) z[i] = c * x[i] + y[i];
}
void lin2(long n, double c, const double* x, const double* y, double* z) {
    for (long i = 0; i < n; ++i) z[i] = c * x[i] - y[i];
}

/// z += c·x, with SUNDIALS' Vaxpy cases (c = ±1: no multiplication).
void axpy(long n, double c, const double* x, double* z) {
    if (c == 1.0)
        for (long i = 0; i < n; ++i) z[i] += x[i];
    else if (c == -1.0)
        for (long i = 0; i < n; ++i) z[i] -= x[i];
    else
        for (long i = 0; i < n; ++i) z[i] += c * x[i];
}

} // namespace

void linear_sum(double a, N_Vector xv, double b, N_Vector yv, N_Vector zv) {
    const long n = NV_LENGTH_S(xv);
    const double* x = NV_DATA_S(xv);
    const double* y = NV_DATA_S(yv);
    double* z = NV_DATA_S(zv);
    // the cases of N_VLinearSum_Serial, in its order
    if (b == 1.0 && zv == yv) return axpy(n, a, x, z); // y += a·x
    if (a == 1.0 && zv == xv) return axpy(n, b, y, z); // x += b·y
    if (a == 1.0 && b == 1.0) {
        for (long i = 0; i < n; ++i) z[i] = x[i] + y[i];
        return;
    }
    if (a == 1.0 && b == -1.0) {
        for (long i = 0; i < n; ++i) z[i] = x[i] - y[i];
        return;
    }
    if (a == -1.0 && b == 1.0) {
        for (long i = 0; i < n; ++i) z[i] = y[i] - x[i];
        return;
    }
    if (a == 1.0) return lin1(n, b, y, x, z);
    if (b == 1.0) return lin1(n, a, x, y, z);
    if (a == -1.0) return lin2(n, b, y, x, z);
    if (b == -1.0) return lin2(n, a, x, y, z);
    if (a == b) {
        for (long i = 0; i < n; ++i) z[i] = a * (x[i] + y[i]);
        return;
    }
    if (a == -b) {
        for (long i = 0; i < n; ++i) z[i] = a * (x[i] - y[i]);
        return;
    }
    for (long i = 0; i < n; ++i) z[i] = a * x[i] + b * y[i];
}

double wrms_norm(N_Vector xv, N_Vector wv) {
    const long n = NV_LENGTH_S(xv);
    const double* x = NV_DATA_S(xv);
    const double* w = NV_DATA_S(wv);
    double s[4] = {0, 0, 0, 0};
    long i = 0;
    for (; i + 4 <= n; i += 4)
        for (int j = 0; j < 4; ++j) {
            const double p = x[i + j] * w[i + j];
            s[j] += p * p;
        }
    for (int j = 0; i < n; ++i, ++j) {
        const double p = x[i] * w[i];
        s[j] += p * p;
    }
    return std::sqrt(((s[0] + s[1]) + (s[2] + s[3])) / static_cast<double>(n));
}

void use_fast_serial_ops(N_Vector v) {
    v->ops->nvlinearsum = linear_sum;
    v->ops->nvwrmsnorm = wrms_norm;
}

} // namespace phynjo::runtime::sundials

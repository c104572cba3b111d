#pragma once
/// \file
/// Several runs of one model in the lanes of a SIMD register: the number type of generated
/// code's lane kernels (phynjo extension, docs/generated-code.md).
///
/// Generated code writes its cores (accelerations_core, energy_core, guards_core, the RK4
/// stages) once, as templates over the number type T, and instantiates them for `double`
/// (one run: the model's functions) and, for a model whose cores allow it, for `Lanes`
/// (kWidth runs at once: a sweep's runs). The functions here give both the same spelling:
/// for `double` they are the <cmath> functions themselves (the same bits as std::sin …); for
/// `Lanes` every arithmetic operation is the IEEE operation of each lane, and sin, cos, exp,
/// log, pow, atan2 … are glibc's libmvec vector kernels (x86-64, `PHYNJO_LIBMVEC`, set by
/// CMake when libmvec links), else the <cmath> function lane by lane.
///
/// What the sweep relies on (tests/codegen/test_lanes.cpp): a lane's result depends on its own
/// operands only — the same bits whatever the other lanes hold (huge, NaN, another run) — so
/// a run's summary row does not depend on which runs shared its register, nor on the thread
/// or rank count. libmvec's results are not libm's (within 4 ulp of the exact value, against
/// libm's 1): a sweep's run and the same run alone (`--output`) agree to rounding, not bit for
/// bit, where the model calls those functions.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

#if defined(PHYNJO_LIBMVEC) && defined(__x86_64__) && defined(__AVX2__)
#include <immintrin.h>
extern "C" {
// glibc's libmvec (2.22), AVX2 variants: four doubles in, four out.
__m256d _ZGVdN4v_sin(__m256d) noexcept __attribute__((const));
__m256d _ZGVdN4v_cos(__m256d) noexcept __attribute__((const));
__m256d _ZGVdN4v_exp(__m256d) noexcept __attribute__((const));
__m256d _ZGVdN4v_log(__m256d) noexcept __attribute__((const));
__m256d _ZGVdN4vv_pow(__m256d, __m256d) noexcept __attribute__((const));
}
#define PHYNJO_LANES_LIBMVEC 4
#elif defined(PHYNJO_LIBMVEC) && defined(__x86_64__) && defined(__SSE2__)
#include <emmintrin.h>
extern "C" {
// glibc's libmvec (2.22), SSE2 variants (every x86-64 CPU): two doubles in, two out.
__m128d _ZGVbN2v_sin(__m128d) noexcept __attribute__((const));
__m128d _ZGVbN2v_cos(__m128d) noexcept __attribute__((const));
__m128d _ZGVbN2v_exp(__m128d) noexcept __attribute__((const));
__m128d _ZGVbN2v_log(__m128d) noexcept __attribute__((const));
__m128d _ZGVbN2vv_pow(__m128d, __m128d) noexcept __attribute__((const));
}
#define PHYNJO_LANES_LIBMVEC 2
#endif

namespace phynjo::runtime::lanes {

/// Runs per register: 4 where the code is compiled for AVX2 with libmvec (-march=native on
/// most x86-64 machines of the last decade), else 2. Generated code's lane kernels use the
/// width they were compiled with and say it in LagrangianSystem::lane_width, which run_many
/// reads: the runtime and a model compiled with other flags still agree.
#if defined(PHYNJO_LANES_LIBMVEC) && PHYNJO_LANES_LIBMVEC == 4
inline constexpr std::size_t kWidth = 4;
#else
inline constexpr std::size_t kWidth = 2;
#endif
/// kWidth doubles, one per run (GCC/Clang vector extension: + − × ÷ lane by lane, a scalar
/// operand broadcast).
using Lanes = double __attribute__((vector_size(kWidth * sizeof(double))));
/// A comparison of Lanes: −1 (true) or 0 per lane.
using Mask = std::int64_t __attribute__((vector_size(kWidth * sizeof(double))));

/// True when Lanes' transcendental functions are libmvec's.
inline constexpr bool kVectorMath =
#if defined(PHYNJO_LANES_LIBMVEC)
    true;
#else
    false;
#endif

// ---- one run: the <cmath> functions ------------------------------------------------------
inline double sin(double x) { return std::sin(x); }
inline double cos(double x) { return std::cos(x); }
inline double tan(double x) { return std::tan(x); }
inline double exp(double x) { return std::exp(x); }
inline double log(double x) { return std::log(x); }
inline double asin(double x) { return std::asin(x); }
inline double acos(double x) { return std::acos(x); }
inline double atan(double x) { return std::atan(x); }
inline double sinh(double x) { return std::sinh(x); }
inline double cosh(double x) { return std::cosh(x); }
inline double tanh(double x) { return std::tanh(x); }
inline double sqrt(double x) { return std::sqrt(x); }
inline double fabs(double x) { return std::fabs(x); }
inline double pow(double x, double y) { return std::pow(x, y); }
inline double atan2(double y, double x) { return std::atan2(y, x); }
/// −1, 0 or 1 (NaN: 0), as generated code's sign(x).
inline double sign(double x) { return x > 0 ? 1.0 : x < 0 ? -1.0 : 0.0; }
inline bool any(bool b) { return b; }
inline bool not_finite(double x) { return !std::isfinite(x); }

// ---- kWidth runs -------------------------------------------------------------------------
namespace detail {
template <class F>
inline Lanes each(Lanes x, F f) {
    Lanes r{};
    for (std::size_t l = 0; l < kWidth; ++l) r[l] = f(x[l]);
    return r;
}
} // namespace detail

#if defined(PHYNJO_LANES_LIBMVEC) && PHYNJO_LANES_LIBMVEC == 4
inline Lanes sin(Lanes x) { return (Lanes)_ZGVdN4v_sin((__m256d)x); }
inline Lanes cos(Lanes x) { return (Lanes)_ZGVdN4v_cos((__m256d)x); }
inline Lanes exp(Lanes x) { return (Lanes)_ZGVdN4v_exp((__m256d)x); }
inline Lanes log(Lanes x) { return (Lanes)_ZGVdN4v_log((__m256d)x); }
inline Lanes pow(Lanes x, Lanes y) { return (Lanes)_ZGVdN4vv_pow((__m256d)x, (__m256d)y); }
#elif defined(PHYNJO_LANES_LIBMVEC)
inline Lanes sin(Lanes x) { return (Lanes)_ZGVbN2v_sin((__m128d)x); }
inline Lanes cos(Lanes x) { return (Lanes)_ZGVbN2v_cos((__m128d)x); }
inline Lanes exp(Lanes x) { return (Lanes)_ZGVbN2v_exp((__m128d)x); }
inline Lanes log(Lanes x) { return (Lanes)_ZGVbN2v_log((__m128d)x); }
inline Lanes pow(Lanes x, Lanes y) { return (Lanes)_ZGVbN2vv_pow((__m128d)x, (__m128d)y); }
#else
inline Lanes sin(Lanes x) { return detail::each(x, [](double v) { return std::sin(v); }); }
inline Lanes cos(Lanes x) { return detail::each(x, [](double v) { return std::cos(v); }); }
inline Lanes exp(Lanes x) { return detail::each(x, [](double v) { return std::exp(v); }); }
inline Lanes log(Lanes x) { return detail::each(x, [](double v) { return std::log(v); }); }
inline Lanes pow(Lanes x, Lanes y) {
    Lanes r{};
    for (std::size_t l = 0; l < kWidth; ++l) r[l] = std::pow(x[l], y[l]);
    return r;
}
#endif
inline Lanes splat(double x) {
    Lanes r{};
    for (std::size_t l = 0; l < kWidth; ++l) r[l] = x;
    return r;
}
inline Lanes pow(Lanes x, double y) { return pow(x, splat(y)); }
inline Lanes pow(double x, Lanes y) { return pow(splat(x), y); }
// the functions libmvec added in glibc 2.35, lane by lane with libm (the same bits as one run)
inline Lanes tan(Lanes x) { return detail::each(x, [](double v) { return std::tan(v); }); }
inline Lanes asin(Lanes x) { return detail::each(x, [](double v) { return std::asin(v); }); }
inline Lanes acos(Lanes x) { return detail::each(x, [](double v) { return std::acos(v); }); }
inline Lanes atan(Lanes x) { return detail::each(x, [](double v) { return std::atan(v); }); }
inline Lanes sinh(Lanes x) { return detail::each(x, [](double v) { return std::sinh(v); }); }
inline Lanes cosh(Lanes x) { return detail::each(x, [](double v) { return std::cosh(v); }); }
inline Lanes tanh(Lanes x) { return detail::each(x, [](double v) { return std::tanh(v); }); }
inline Lanes sqrt(Lanes x) { return detail::each(x, [](double v) { return std::sqrt(v); }); }
inline Lanes atan2(Lanes y, Lanes x) {
    Lanes r{};
    for (std::size_t l = 0; l < kWidth; ++l) r[l] = std::atan2(y[l], x[l]);
    return r;
}
inline Lanes atan2(Lanes y, double x) { return atan2(y, splat(x)); }
inline Lanes atan2(double y, Lanes x) { return atan2(splat(y), x); }
inline Lanes fabs(Lanes x) { return detail::each(x, [](double v) { return std::fabs(v); }); }
inline Lanes sign(Lanes x) { return detail::each(x, [](double v) { return v > 0 ? 1.0 : v < 0 ? -1.0 : 0.0; }); }
inline bool any(Mask m) {
    bool r = false;
    for (std::size_t l = 0; l < kWidth; ++l) r = r || m[l] != 0;
    return r;
}
inline bool not_finite(Lanes x) {
    bool r = false;
    for (std::size_t l = 0; l < kWidth; ++l) r = r || !std::isfinite(x[l]);
    return r;
}

/// `x` as the number type T: itself for double, in every lane for Lanes (−0 stays −0).
template <class T>
inline T as(double x) {
    if constexpr (sizeof(T) == sizeof(double)) return x;
    else return splat(x);
}
template <class T>
inline T as(Lanes x) {
    static_assert(sizeof(T) == sizeof(Lanes), "lanes are never narrowed to one run");
    return x;
}
/// kWidth consecutive doubles as Lanes, and back.
inline Lanes load(const double* a) {
    Lanes v{};
    std::memcpy(&v, a, sizeof v);
    return v;
}
inline void store(double* a, Lanes v) { std::memcpy(a, &v, sizeof v); }

/// The time in an error message: lane 0's (a failing lane is re-run alone, in every lane).
inline double first(double x) { return x; }
inline double first(Lanes x) { return x[0]; }

} // namespace phynjo::runtime::lanes

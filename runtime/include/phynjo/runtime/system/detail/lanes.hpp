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
//
/// It includes no header (a model kernel includes no standard header: it compiles in a fraction
/// of the time, docs/command-line.md, *Kernels*): the math is GCC's builtins, which are the
/// <cmath> functions themselves (the same calls, the same bits), the libmvec kernels declared
/// on the vector type itself (passed in the same registers as <immintrin.h>'s __m256d/__m128d).

#if defined(PHYNJO_LIBMVEC) && defined(__x86_64__) && defined(__AVX2__)
#define PHYNJO_LANES_LIBMVEC 4
#elif defined(PHYNJO_LIBMVEC) && defined(__x86_64__) && defined(__SSE2__)
#define PHYNJO_LANES_LIBMVEC 2
#endif

namespace phynjo::runtime::lanes {

/// size_type, without <cstddef>.
using size_type = decltype(sizeof 0);

/// Runs per register: 4 where the code is compiled for AVX2 with libmvec (-march=native on
/// most x86-64 machines of the last decade), else 2. Generated code's lane kernels use the
/// width they were compiled with and say it in LagrangianSystem::lane_width, which run_many
/// reads: the runtime and a model compiled with other flags still agree.
#if defined(PHYNJO_LANES_LIBMVEC) && PHYNJO_LANES_LIBMVEC == 4
inline constexpr size_type kWidth = 4;
#else
inline constexpr size_type kWidth = 2;
#endif
/// kWidth doubles, one per run (GCC/Clang vector extension: + − × ÷ lane by lane, a scalar
/// operand broadcast).
using Lanes = double __attribute__((vector_size(kWidth * sizeof(double))));
/// A comparison of Lanes: −1 (true) or 0 per lane.
using Mask = __INT64_TYPE__ __attribute__((vector_size(kWidth * sizeof(double))));

/// True when Lanes' transcendental functions are libmvec's.
inline constexpr bool kVectorMath =
#if defined(PHYNJO_LANES_LIBMVEC)
    true;
#else
    false;
#endif

// ---- one run: the <cmath> functions ------------------------------------------------------
inline double sin(double x) { return __builtin_sin(x); }
inline double cos(double x) { return __builtin_cos(x); }
inline double tan(double x) { return __builtin_tan(x); }
inline double exp(double x) { return __builtin_exp(x); }
inline double log(double x) { return __builtin_log(x); }
inline double asin(double x) { return __builtin_asin(x); }
inline double acos(double x) { return __builtin_acos(x); }
inline double atan(double x) { return __builtin_atan(x); }
inline double sinh(double x) { return __builtin_sinh(x); }
inline double cosh(double x) { return __builtin_cosh(x); }
inline double tanh(double x) { return __builtin_tanh(x); }
inline double sqrt(double x) { return __builtin_sqrt(x); }
inline double fabs(double x) { return __builtin_fabs(x); }
inline double pow(double x, double y) { return __builtin_pow(x, y); }
inline double atan2(double y, double x) { return __builtin_atan2(y, x); }
/// −1, 0 or 1 (NaN: 0), as generated code's sign(x).
inline double sign(double x) { return x > 0 ? 1.0 : x < 0 ? -1.0 : 0.0; }
inline bool any(bool b) { return b; }
inline bool not_finite(double x) { return !__builtin_isfinite(x); }

// ---- kWidth runs -------------------------------------------------------------------------
namespace detail {
template <class F>
inline Lanes each(Lanes x, F f) {
    Lanes r{};
    for (size_type l = 0; l < kWidth; ++l) r[l] = f(x[l]);
    return r;
}
} // namespace detail

#if defined(PHYNJO_LANES_LIBMVEC)
// glibc's libmvec (2.22): the AVX2 variants (four doubles) or the SSE2 ones (two, every x86-64 CPU)
#if PHYNJO_LANES_LIBMVEC == 4
#define PHYNJO_LANES_MVEC(name, args) _ZGVdN4##args##_##name
#else
#define PHYNJO_LANES_MVEC(name, args) _ZGVbN2##args##_##name
#endif
extern "C" {
Lanes PHYNJO_LANES_MVEC(sin, v)(Lanes) noexcept __attribute__((const));
Lanes PHYNJO_LANES_MVEC(cos, v)(Lanes) noexcept __attribute__((const));
Lanes PHYNJO_LANES_MVEC(exp, v)(Lanes) noexcept __attribute__((const));
Lanes PHYNJO_LANES_MVEC(log, v)(Lanes) noexcept __attribute__((const));
Lanes PHYNJO_LANES_MVEC(pow, vv)(Lanes, Lanes) noexcept __attribute__((const));
}
inline Lanes sin(Lanes x) { return PHYNJO_LANES_MVEC(sin, v)(x); }
inline Lanes cos(Lanes x) { return PHYNJO_LANES_MVEC(cos, v)(x); }
inline Lanes exp(Lanes x) { return PHYNJO_LANES_MVEC(exp, v)(x); }
inline Lanes log(Lanes x) { return PHYNJO_LANES_MVEC(log, v)(x); }
inline Lanes pow(Lanes x, Lanes y) { return PHYNJO_LANES_MVEC(pow, vv)(x, y); }
#undef PHYNJO_LANES_MVEC
#else
inline Lanes sin(Lanes x) { return detail::each(x, [](double v) { return __builtin_sin(v); }); }
inline Lanes cos(Lanes x) { return detail::each(x, [](double v) { return __builtin_cos(v); }); }
inline Lanes exp(Lanes x) { return detail::each(x, [](double v) { return __builtin_exp(v); }); }
inline Lanes log(Lanes x) { return detail::each(x, [](double v) { return __builtin_log(v); }); }
inline Lanes pow(Lanes x, Lanes y) {
    Lanes r{};
    for (size_type l = 0; l < kWidth; ++l) r[l] = __builtin_pow(x[l], y[l]);
    return r;
}
#endif
inline Lanes splat(double x) {
    Lanes r{};
    for (size_type l = 0; l < kWidth; ++l) r[l] = x;
    return r;
}
inline Lanes pow(Lanes x, double y) { return pow(x, splat(y)); }
inline Lanes pow(double x, Lanes y) { return pow(splat(x), y); }
// the functions libmvec added in glibc 2.35, lane by lane with libm (the same bits as one run)
inline Lanes tan(Lanes x) { return detail::each(x, [](double v) { return __builtin_tan(v); }); }
inline Lanes asin(Lanes x) { return detail::each(x, [](double v) { return __builtin_asin(v); }); }
inline Lanes acos(Lanes x) { return detail::each(x, [](double v) { return __builtin_acos(v); }); }
inline Lanes atan(Lanes x) { return detail::each(x, [](double v) { return __builtin_atan(v); }); }
inline Lanes sinh(Lanes x) { return detail::each(x, [](double v) { return __builtin_sinh(v); }); }
inline Lanes cosh(Lanes x) { return detail::each(x, [](double v) { return __builtin_cosh(v); }); }
inline Lanes tanh(Lanes x) { return detail::each(x, [](double v) { return __builtin_tanh(v); }); }
inline Lanes sqrt(Lanes x) { return detail::each(x, [](double v) { return __builtin_sqrt(v); }); }
inline Lanes atan2(Lanes y, Lanes x) {
    Lanes r{};
    for (size_type l = 0; l < kWidth; ++l) r[l] = __builtin_atan2(y[l], x[l]);
    return r;
}
inline Lanes atan2(Lanes y, double x) { return atan2(y, splat(x)); }
inline Lanes atan2(double y, Lanes x) { return atan2(splat(y), x); }
inline Lanes fabs(Lanes x) { return detail::each(x, [](double v) { return __builtin_fabs(v); }); }
inline Lanes sign(Lanes x) { return detail::each(x, [](double v) { return v > 0 ? 1.0 : v < 0 ? -1.0 : 0.0; }); }
inline bool any(Mask m) {
    bool r = false;
    for (size_type l = 0; l < kWidth; ++l) r = r || m[l] != 0;
    return r;
}
inline bool not_finite(Lanes x) {
    bool r = false;
    for (size_type l = 0; l < kWidth; ++l) r = r || !__builtin_isfinite(x[l]);
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
    __builtin_memcpy(&v, a, sizeof v);
    return v;
}
inline void store(double* a, Lanes v) { __builtin_memcpy(a, &v, sizeof v); }

/// The time in an error message: lane 0's (a failing lane is re-run alone, in every lane).
inline double first(double x) { return x; }
inline double first(Lanes x) { return x[0]; }

} // namespace phynjo::runtime::lanes

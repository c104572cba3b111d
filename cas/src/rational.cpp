#include "phynjo/cas/rational.hpp"

#include "phynjo/cas/errors.hpp"

#include <charconv>
#include <cmath>
#include <limits>

namespace phynjo::cas {

std::optional<mpq_class> parse_decimal(std::string_view s) {
    // digits [ '.' digits ] [ (e|E) [+|-] digits ], with at least one digit in the mantissa.
    std::size_t i = 0;
    std::string mantissa;
    long frac_digits = 0;
    while (i < s.size() && s[i] >= '0' && s[i] <= '9') mantissa += s[i++];
    if (i < s.size() && s[i] == '.') {
        ++i;
        while (i < s.size() && s[i] >= '0' && s[i] <= '9') {
            mantissa += s[i++];
            ++frac_digits;
        }
    }
    if (mantissa.empty()) return std::nullopt;
    long exponent = 0;
    if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
        ++i;
        bool negative = false;
        if (i < s.size() && (s[i] == '+' || s[i] == '-')) negative = s[i++] == '-';
        if (i == s.size()) return std::nullopt;
        long e = 0;
        while (i < s.size() && s[i] >= '0' && s[i] <= '9') {
            e = e * 10 + (s[i++] - '0');
            if (e > 100'000) return std::nullopt; // far beyond the limit below
        }
        exponent = negative ? -e : e;
    }
    if (i != s.size()) return std::nullopt;
    // Drop leading zeros so that the size limit counts significant digits only.
    const std::size_t nz = mantissa.find_first_not_of('0');
    mantissa = nz == std::string::npos ? "0" : mantissa.substr(nz);
    const long scale = exponent - frac_digits;
    // Every number the CAS holds (at most limits::max_number_bits = 100,000 bits, i.e. 30,103
    // decimal digits) must be readable back from its printed form.
    constexpr long max_digits = limits::max_literal_digits;
    if (static_cast<long>(mantissa.size()) > max_digits || scale > max_digits || scale < -max_digits)
        return std::nullopt;
    if (mantissa == "0") return mpq_class(0);
    mpz_class num(mantissa, 10), p10;
    mpz_ui_pow_ui(p10.get_mpz_t(), 10, static_cast<unsigned long>(scale < 0 ? -scale : scale));
    mpq_class q;
    if (scale >= 0) q = mpq_class(num * p10);
    else q = mpq_class(num, p10);
    q.canonicalize();
    if (mpz_sizeinbase(q.get_num_mpz_t(), 2) > limits::max_number_bits ||
        mpz_sizeinbase(q.get_den_mpz_t(), 2) > limits::max_number_bits)
        return std::nullopt;
    return q;
}

namespace {
// Correct rounding of a/b (a, b > 0) to a `digits`-bit significand:
// scale so the integer quotient has at least digits + 2 bits, keep a sticky bit for the
// remainder, then round half to even.
template <typename T>
T to_float(const mpq_class& q) {
    constexpr int digits = std::numeric_limits<T>::digits;
    const int sign = sgn(q);
    if (sign == 0) return T(0);
    mpz_class a = abs(q.get_num()), b = q.get_den();
    const long shift = static_cast<long>(digits + 2) -
                       (static_cast<long>(mpz_sizeinbase(a.get_mpz_t(), 2)) -
                        static_cast<long>(mpz_sizeinbase(b.get_mpz_t(), 2)));
    if (shift > 0) mpz_mul_2exp(a.get_mpz_t(), a.get_mpz_t(), static_cast<mp_bitcnt_t>(shift));
    else if (shift < 0) mpz_mul_2exp(b.get_mpz_t(), b.get_mpz_t(), static_cast<mp_bitcnt_t>(-shift));
    mpz_class quot, rem;
    mpz_tdiv_qr(quot.get_mpz_t(), rem.get_mpz_t(), a.get_mpz_t(), b.get_mpz_t());
    const bool sticky = rem != 0;
    const long bits = static_cast<long>(mpz_sizeinbase(quot.get_mpz_t(), 2)); // digits+2 or digits+3
    long drop = bits - digits;
    // Subnormal results have fewer significand bits: drop more.
    const long exp2 = bits - 1 - shift; // the value lies in [2^exp2, 2^(exp2+1))
    constexpr long min_exp = std::numeric_limits<T>::min_exponent - 1; // exponent of the smallest normal
    if (exp2 < min_exp) drop += min_exp - exp2;
    if (drop > bits + 1) return sign < 0 ? -T(0) : T(0);
    mpz_class mant;
    mpz_fdiv_q_2exp(mant.get_mpz_t(), quot.get_mpz_t(), static_cast<mp_bitcnt_t>(drop));
    const bool half = mpz_tstbit(quot.get_mpz_t(), static_cast<mp_bitcnt_t>(drop - 1));
    bool below_half_nonzero = sticky;
    for (long i = 0; i < drop - 1 && !below_half_nonzero; ++i)
        below_half_nonzero = mpz_tstbit(quot.get_mpz_t(), static_cast<mp_bitcnt_t>(i));
    if (half && (below_half_nonzero || mpz_odd_p(mant.get_mpz_t()))) ++mant;
    // mant has at most digits + 1 bits; convert exactly through two 32-bit halves.
    T m = 0;
    const std::size_t nbits = mpz_sizeinbase(mant.get_mpz_t(), 2);
    for (long i = static_cast<long>(nbits) - 1; i >= 0; --i)
        m = m * 2 + (mpz_tstbit(mant.get_mpz_t(), static_cast<mp_bitcnt_t>(i)) ? 1 : 0);
    const long e = drop - shift;
    const T r = std::ldexp(m, static_cast<int>(std::max<long>(std::min<long>(e, 100000), -100000)));
    return sign < 0 ? -r : r;
}
} // namespace

double to_double(const mpq_class& q) { return to_float<double>(q); }
long double to_long_double(const mpq_class& q) { return to_float<long double>(q); }

std::string double_literal(double x) {
    char buf[64];
    auto [end, ec] = std::to_chars(buf, buf + sizeof buf, x);
    std::string s(buf, end);
    if (s.find_first_of(".eEn") == std::string::npos) s += ".0"; // n: inf / nan
    return s;
}

} // namespace phynjo::cas

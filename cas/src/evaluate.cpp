#include "phynjo/cas/evaluate.hpp"
#include "phynjo/cas/node_map.hpp"

#include "phynjo/cas/errors.hpp"
#include "phynjo/cas/print.hpp"
#include "phynjo/cas/rational.hpp"

#include <cmath>

namespace phynjo::cas {

namespace {

template <typename T>
T number_value(Expr x) {
    // an integer below 2^61: the conversion rounds to nearest, as to_double does for any rational
    if (x->small) return static_cast<T>(x->small_value);
    if constexpr (std::is_same_v<T, double>) return to_double(x.value());
    else return to_long_double(x.value());
}

template <typename T>
T evaluate_impl(Expr e, const Bindings<T>& values, NodeMap<T>& memo) {
    auto rec = [&](auto&& self, Expr x) -> T {
        if (const T* m = memo.find(x)) return *m;
        T r{};
        switch (x.kind()) {
        case Kind::Number: r = number_value<T>(x); break;
        case Kind::Constant: r = T(3.141592653589793238462643383279502884L); break;
        case Kind::Symbol:
        case Kind::TimeDerivative: {
            auto it = values.find(x);
            if (it == values.end()) throw EvaluationError("no value for '" + to_string(x) + "'");
            r = it->second;
            break;
        }
        case Kind::Function: {
            const T u = self(self, x.args()[0]);
            switch (static_cast<Function>(x->sub)) {
            case Function::Sin: r = std::sin(u); break;
            case Function::Cos: r = std::cos(u); break;
            case Function::Tan: r = std::tan(u); break;
            case Function::Exp: r = std::exp(u); break;
            case Function::Log: r = std::log(u); break;
            case Function::Asin: r = std::asin(u); break;
            case Function::Acos: r = std::acos(u); break;
            case Function::Atan: r = std::atan(u); break;
            case Function::Sinh: r = std::sinh(u); break;
            case Function::Cosh: r = std::cosh(u); break;
            case Function::Tanh: r = std::tanh(u); break;
            case Function::Abs: r = std::fabs(u); break;
            case Function::Sign: r = u > 0 ? T(1) : u < 0 ? T(-1) : T(0); break;
            case Function::Atan2: r = std::atan2(u, self(self, x.args()[1])); break;
            }
            break;
        }
        case Kind::Pow: {
            const T b = self(self, x.args()[0]);
            const Expr ex = x.args()[1];
            if (ex.is_integer() && abs(ex.value().get_num()) <= 64) {
                // exact repeated multiplication for small integer powers
                long n = ex.value().get_num().get_si();
                T acc = 1, base = n < 0 ? T(1) / b : b;
                for (long k = n < 0 ? -n : n; k; k >>= 1) {
                    if (k & 1) acc *= base;
                    base *= base;
                }
                r = acc;
            } else r = std::pow(b, self(self, ex));
            break;
        }
        case Kind::Mul: {
            r = number_value<T>(x->number);
            for (Expr f : x.args()) r *= self(self, f);
            break;
        }
        case Kind::Add: {
            r = number_value<T>(x->number);
            for (std::uint32_t i = 0; i < x->nargs; ++i) r += number_value<T>(x->coefs[i]) * self(self, x.args()[i]);
            break;
        }
        }
        if (!std::isfinite(r))
            throw EvaluationError("'" + to_string(x) + "' is not finite (" + (std::isnan(r) ? "NaN" : "infinite") + ")");
        memo.try_emplace(x, r);
        return r;
    };
    return rec(rec, e);
}

} // namespace

double evaluate(Expr e, const Bindings<double>& values) {
    NodeMap<double> memo;
    return evaluate_impl<double>(e, values, memo);
}
std::vector<double> evaluate(std::span<const Expr> es, const Bindings<double>& values) {
    NodeMap<double> memo;
    std::vector<double> out;
    out.reserve(es.size());
    for (Expr e : es) out.push_back(evaluate_impl<double>(e, values, memo));
    return out;
}
long double evaluate_extended(Expr e, const Bindings<long double>& values) {
    NodeMap<long double> memo;
    return evaluate_impl<long double>(e, values, memo);
}

} // namespace phynjo::cas

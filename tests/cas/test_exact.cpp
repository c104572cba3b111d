// Exactness: numbers are rationals, literals are read exactly, conversions round correctly.
#include "phynjo/cas/cas.hpp"
#include "phynjo/grammar/expression.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <cstdlib>
#include <random>

using namespace phynjo::cas;
using phynjo::grammar::parse;

TEST_CASE("rational arithmetic is exact", "[cas][exact]") {
    CHECK(rational(1, 3) + rational(1, 6) == rational(1, 2));
    CHECK(parse("1/3 + 1/6") == rational(1, 2));
    CHECK(rational(1, 10) + rational(2, 10) == rational(3, 10)); // 0.1 + 0.2 == 0.3 exactly
    CHECK(parse("0.1 + 0.2") == parse("0.3"));
    CHECK(rational(6, 4) == rational(3, 2));
    CHECK(rational(-2, -4) == rational(1, 2));
    // big numbers do not overflow: (10^40 + 1) - 10^40 == 1
    const Expr big = pow(Expr(10), Expr(40));
    CHECK(big + 1 - big == Expr(1));
    CHECK(to_string(big) == "10000000000000000000000000000000000000000");
    // int64 fast path and GMP path agree around the boundary
    const Expr near = integer((1LL << 61) - 1);
    CHECK(near + near - near == near);
    CHECK(to_string(near * near) == "5316911983139663487003542222693990401");
    CHECK_THROWS_AS(rational(1, 0), DomainError);
}

TEST_CASE("decimal literals are read exactly", "[cas][exact]") {
    CHECK(parse("9.81") == rational(981, 100));
    CHECK(parse("1e-3") == rational(1, 1000));
    CHECK(parse(".5") == rational(1, 2));
    CHECK(parse("0.25") == rational(1, 4));
    CHECK(parse("6.674e-11") == rational(6674, 1000) * pow(Expr(10), Expr(-11)));
    CHECK(parse("1E+3") == Expr(1000));
    CHECK(parse("007") == Expr(7));
    CHECK(parse("3.") == Expr(3));
    CHECK_FALSE(parse_decimal("1e").has_value());
    CHECK_FALSE(parse_decimal("1e99999").has_value()); // beyond the documented limit
    CHECK(parse_decimal("1e-9999").has_value());
}

TEST_CASE("exact powers and roots", "[cas][exact]") {
    CHECK(pow(Expr(4), rational(1, 2)) == Expr(2));
    CHECK(pow(Expr(8), rational(2, 3)) == Expr(4));
    CHECK(pow(rational(9, 4), rational(1, 2)) == rational(3, 2));
    CHECK(pow(rational(9, 4), rational(-1, 2)) == rational(2, 3));
    CHECK(pow(Expr(2), Expr(10)) == Expr(1024));
    CHECK(pow(Expr(2), Expr(-2)) == rational(1, 4));
    CHECK(pow(Expr(-2), Expr(3)) == Expr(-8));
    CHECK(pow(Expr(2), rational(3, 2)) == 2 * sqrt(Expr(2)));
    CHECK(sqrt(Expr(2)) * sqrt(Expr(2)) == Expr(2));
    CHECK(pow(Expr(0), Expr(3)) == Expr(0));
    CHECK_THROWS_AS(pow(Expr(0), Expr(-1)), DomainError);
    CHECK_THROWS_AS(pow(Expr(3), pow(Expr(10), Expr(7))), LimitError);
    CHECK(pow(Expr(1), pow(Expr(10), Expr(7))) == Expr(1));
    CHECK(pow(Expr(-1), pow(Expr(10), Expr(7))) == Expr(1));
}

TEST_CASE("to_double rounds correctly, as strtod does", "[cas][exact]") {
    const char* cases[] = {"9.81", "0.1", "0.3", "1e-3", "6.674e-11", "2.2250738585072011e-308",
                           "1.7976931348623157e308", "9007199254740993", "4.9406564584124654e-324",
                           "2.4703282292062328e-324", "0.30000000000000004", "123456789012345678901234567890",
                           "1e-320", "3.14159265358979323846264338327950288", "1e300", "5e-324", "1e-400", "1e400"};
    for (const char* s : cases) {
        INFO(s);
        CHECK(to_double(*parse_decimal(s)) == std::strtod(s, nullptr));
        CHECK(to_long_double(*parse_decimal(s)) == std::strtold(s, nullptr));
    }
    // 20,000 random decimals with up to 25 significant digits and exponents across the range
    std::mt19937_64 rng(12345);
    for (int i = 0; i < 20000; ++i) {
        std::string digits = std::to_string(rng() % 1000000000ULL) + std::to_string(rng() % 1000000000ULL);
        digits = digits.substr(0, 1 + rng() % digits.size());
        const int exponent = static_cast<int>(rng() % 640) - 330;
        const std::string s = digits + "e" + std::to_string(exponent);
        INFO(s);
        const auto q = parse_decimal(s);
        REQUIRE(q);
        REQUIRE(to_double(*q) == std::strtod(s.c_str(), nullptr));
        REQUIRE(to_long_double(*q) == std::strtold(s.c_str(), nullptr));
        const mpq_class neg = -*q;
        REQUIRE(to_double(neg) == -std::strtod(s.c_str(), nullptr));
    }
}

TEST_CASE("double literals read back exactly", "[cas][exact]") {
    std::mt19937_64 rng(7);
    for (int i = 0; i < 10000; ++i) {
        double x;
        const std::uint64_t bits = rng();
        std::memcpy(&x, &bits, sizeof x);
        if (!std::isfinite(x)) continue;
        const std::string s = double_literal(x);
        INFO(s);
        REQUIRE(s.find_first_of(".e") != std::string::npos);
        REQUIRE(std::strtod(s.c_str(), nullptr) == x);
    }
    CHECK(double_literal(2.0) == "2.0");
    CHECK(double_literal(9.81) == "9.81");
}

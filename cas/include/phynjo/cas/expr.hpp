#pragma once
/// \file
/// Immutable, hash-consed symbolic expressions with exact (GMP) rational arithmetic.
///
/// Every expression is a pointer to one interned `Node` in the current thread's `Pool`:
/// equal structure is the same node, so `==` is a pointer compare and `hash()` is stored.
/// Nodes are only made through the canonicalizing factories below (`add`, `mul`, `pow`,
/// `sin`, …), which keep these invariants (asserted in debug builds):
///
/// - `Add`: a constant term (a Number, possibly 0) plus at least one term `c_i * r_i` where the
///   coefficient `c_i` is a nonzero Number and the *rest* `r_i` is neither a Number, an Add,
///   nor a Mul with a coefficient; rests are unique and sorted by `compare`; with one term the
///   constant is nonzero.
/// - `Mul`: a coefficient (a nonzero Number, 1 if absent) times at least one factor; factors
///   are neither Numbers nor Muls, their bases (`b` of `b^e`) are unique and sorted; a lone
///   factor has a coefficient other than 1 and is not an Add (a number times a sum is
///   distributed, as in SymPy). A sum standing as a factor among others is *primitive*: its
///   coefficients have no common rational content and its first term is positive, the
///   content having moved into the product's coefficient. This keeps `mul` associative
///   (`((x+y)*2)*c` and `(x+y)*(2*c)` are one node) while `e - e` is 0 for every e.
/// - `Pow`: `b^e` with e ≠ 0, e ≠ 1, b ≠ 1; a Number base has a non-integer exponent; a
///   Mul base or a Pow base has a non-integer exponent; an Add base under an integer
///   exponent is primitive.
/// - `TimeDerivative`: `x'`, `x''`, … of a Symbol other than `t` (time), order ≥ 1.
#include <gmpxx.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace phynjo::cas {

/// The node kinds, declared once. Every pass switches over all of them without a `default`
/// label, so that adding a kind does not compile until every pass handles it
/// (`-Werror=switch`).
enum class Kind : std::uint8_t { Number, Constant, Symbol, TimeDerivative, Function, Pow, Mul, Add };

/// Elementary functions: of one argument, and atan2(y, x) of two.
enum class Function : std::uint8_t { Sin, Cos, Tan, Exp, Log, Asin, Acos, Atan, Sinh, Cosh, Tanh, Abs, Sign, Atan2 };

/// Exact named constants.
enum class Constant : std::uint8_t { Pi };

/// The name of a function as written in the input syntax (`sin`, …).
std::string_view function_name(Function f);
/// How many arguments a function takes: 2 for atan2, 1 for the others.
std::size_t function_arity(Function f);

struct Node;
class Pool;

/// A handle to an interned expression node (one pointer). Default-constructed handles are
/// null; every factory returns a non-null handle.
class Expr {
public:
    constexpr Expr() noexcept = default;
    /// The integer `v`.
    Expr(int v);       // NOLINT(google-explicit-constructor): numbers read naturally in formulas
    Expr(long v);      // NOLINT(google-explicit-constructor)
    Expr(long long v); // NOLINT(google-explicit-constructor)
    /// The exact rational `v`.
    explicit Expr(const mpq_class& v);
    /// Wraps a node (for passes over the tree).
    explicit constexpr Expr(const Node* n) noexcept : n_(n) {}

    [[nodiscard]] const Node* get() const noexcept { return n_; }
    [[nodiscard]] const Node& operator*() const noexcept { return *n_; }
    [[nodiscard]] const Node* operator->() const noexcept { return n_; }
    [[nodiscard]] bool is_null() const noexcept { return n_ == nullptr; }

    [[nodiscard]] Kind kind() const noexcept;
    [[nodiscard]] std::uint64_t hash() const noexcept;
    [[nodiscard]] bool is_number() const noexcept { return kind() == Kind::Number; }
    [[nodiscard]] bool is_zero() const noexcept;
    [[nodiscard]] bool is_one() const noexcept;
    /// True for a Number that is an integer.
    [[nodiscard]] bool is_integer() const noexcept;
    /// True for Symbol and TimeDerivative nodes: the things `diff` differentiates by.
    [[nodiscard]] bool is_atom_variable() const noexcept;
    /// The children: Add terms (rests), Mul factors, Pow {base, exponent}, Function {arg},
    /// TimeDerivative {symbol}. Empty for leaves.
    [[nodiscard]] std::span<const Expr> args() const noexcept;
    /// The exact value of a Number.
    [[nodiscard]] const mpq_class& value() const noexcept;

    friend bool operator==(Expr a, Expr b) noexcept { return a.n_ == b.n_; }

private:
    const Node* n_ = nullptr;
};

/// One interned node. Read-only; made only by the factories.
struct Node {
    Kind kind;
    std::uint8_t sub = 0;         ///< Function or Constant id; TimeDerivative order
    bool small = false;           ///< Number: the value is an integer that fits `small_value`
    std::uint32_t nargs = 0;
    std::uint32_t pool_id = 0;    ///< the Pool that owns this node
    std::uint64_t hash = 0;       ///< structural, identical across runs and platforms
    std::uint64_t atom_mask = 0;  ///< Bloom mask of the atoms (symbols, x', …) inside
    std::int64_t small_value = 0; ///< Number with `small`: the value
    const mpq_class* value = nullptr; ///< Number: the exact value
    std::string_view name;        ///< Symbol: the name
    const Expr* args = nullptr;   ///< children (see Expr::args)
    const Expr* coefs = nullptr;  ///< Add: the Number coefficient of each term, parallel to args
    Expr number;                  ///< Add: the constant term; Mul: the coefficient (Numbers)
};

inline Kind Expr::kind() const noexcept { return n_->kind; }
inline std::uint64_t Expr::hash() const noexcept { return n_->hash; }
inline std::span<const Expr> Expr::args() const noexcept { return {n_->args, n_->nargs}; }
inline const mpq_class& Expr::value() const noexcept { return *n_->value; }
inline bool Expr::is_zero() const noexcept { return n_->kind == Kind::Number && n_->small && n_->small_value == 0; }
inline bool Expr::is_one() const noexcept { return n_->kind == Kind::Number && n_->small && n_->small_value == 1; }
inline bool Expr::is_atom_variable() const noexcept {
    return n_->kind == Kind::Symbol || n_->kind == Kind::TimeDerivative;
}

/// Add coefficients (parallel to args()).
inline std::span<const Expr> add_coefficients(Expr e) noexcept { return {e->coefs, e->nargs}; }
/// Add: the constant term. Mul: the numeric coefficient. Others: null.
inline Expr numeric_part(Expr e) noexcept { return e->number; }

// ---- factories (canonicalizing) -------------------------------------------------------

Expr integer(long long v);
Expr integer(const mpz_class& v);
Expr rational(long long p, long long q); ///< p/q; throws DomainError for q = 0
Expr number(const mpq_class& v);
Expr pi();
/// A symbol. The name `t` is time (d/dt t = 1).
Expr symbol(std::string_view name);
/// The time symbol `t`.
Expr time_symbol();

Expr add(std::span<const Expr> terms);
Expr add(std::initializer_list<Expr> terms);
Expr mul(std::span<const Expr> factors);
Expr mul(std::initializer_list<Expr> factors);
/// b^e. Exact rational powers are evaluated (`4^(1/2)` → 2), `0^e` with e < 0 throws
/// DomainError, results with more than `limits::max_number_bits` bits throw LimitError.
Expr pow(Expr base, Expr exponent);
Expr sqrt(Expr x);
Expr function(Function f, Expr arg);
/// Any function from its arguments (function_arity(f) of them, else std::invalid_argument).
Expr function(Function f, std::span<const Expr> args);
Expr sin(Expr x);
Expr cos(Expr x);
Expr tan(Expr x);
Expr exp(Expr x);
Expr log(Expr x);
/// asin, acos (|x| ≤ 1), atan, sinh, cosh, tanh; abs (derivative sign(x)) and sign
/// (−1, 0 or 1; derivative 0).
Expr asin(Expr x);
Expr acos(Expr x);
Expr atan(Expr x);
Expr sinh(Expr x);
Expr cosh(Expr x);
Expr tanh(Expr x);
Expr abs(Expr x);
Expr sign(Expr x);
/// atan2(y, x): the angle of the point (x, y), in (−π, π]. Exact where the angle is
/// (a coordinate zero, |x| = |y|; atan(y/x) for a number x > 0); derivative
/// (x·dy − y·dx)/(x² + y²); undefined (DomainError) at (0, 0).
Expr atan2(Expr y, Expr x);
/// The total time derivative `e'`, treating every symbol except `t` as a function of time:
/// `x'` for a symbol, and the sum, product and chain rules for the rest (`(x^2)'` = `2*x*x'`).
Expr time_derivative(Expr e);

Expr operator+(Expr a, Expr b);
Expr operator-(Expr a, Expr b);
Expr operator*(Expr a, Expr b);
Expr operator/(Expr a, Expr b);
Expr operator-(Expr a);

/// The canonical total order of the factories (by structural hash, then structure):
/// negative, zero or positive. Identical across runs.
int compare(Expr a, Expr b) noexcept;

/// If `e` is a symbol, its name; if a time derivative, the name of its symbol.
std::string_view symbol_name(Expr e) noexcept;
/// Order of a TimeDerivative node (0 for anything else).
int derivative_order(Expr e) noexcept;

/// Number of distinct nodes reachable from `e` (its DAG size).
std::size_t dag_size(Expr e);
std::size_t dag_size(std::span<const Expr> es);
/// Number of nodes of `e` as a tree (shared subtrees counted each time), saturating.
std::size_t tree_size(Expr e);

} // namespace phynjo::cas

template <>
struct std::hash<phynjo::cas::Expr> {
    std::size_t operator()(phynjo::cas::Expr e) const noexcept { return static_cast<std::size_t>(e.hash()); }
};

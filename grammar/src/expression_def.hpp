#pragma once
// The X3 rules of the expression language (docs/language.md, *Expressions*):
//   expression := product (('+' | '-') product)*
//   product    := unary (('*' | '/') unary)*
//   unary      := '-'* power                      (-x^2 is -(x^2))
//   power      := postfix ('^' unary)?            (right associative, 2^-1 allowed)
//   postfix    := primary '\''*
//   primary    := number | name '(' expression ')' | name | '(' expression ')'
// Recursion (parentheses, calls, exponents) passes through `guarded[…]`, which counts depth.
#include "expression_rules.hpp"

#include <boost/spirit/home/x3/support/utility/annotate_on_success.hpp>

namespace phynjo::grammar::parser {

/// `guarded[p]`: p, with the nesting depth counted against DepthCounter::limit.
template <typename Subject>
struct guard_directive : x3::unary_parser<Subject, guard_directive<Subject>> {
    using base_type = x3::unary_parser<Subject, guard_directive<Subject>>;
    static bool const is_pass_through_unary = true;
    static bool const handles_container = Subject::handles_container;
    constexpr guard_directive(Subject const& s) : base_type(s) {}

    template <typename Iterator, typename Context, typename RContext, typename Attribute>
    bool parse(Iterator& first, Iterator const& last, Context const& context, RContext& rcontext,
               Attribute& attr) const {
        DepthCounter& d = x3::get<depth_tag>(context).get();
        if (d.depth >= d.limit) throw DepthExceeded{&*first};
        ++d.depth;
        struct Leave {
            DepthCounter& d;
            ~Leave() { --d.depth; }
        } leave{d};
        return this->subject.parse(first, last, context, rcontext, attr);
    }
};
struct guard_gen {
    template <typename Subject>
    constexpr guard_directive<typename x3::extension::as_parser<Subject>::value_type>
    operator[](Subject const& subject) const {
        return {x3::as_parser(subject)};
    }
};
inline constexpr guard_gen guarded{};

struct number_class : annotate_position {};
struct call_class : annotate_position {};
struct paren_class : annotate_position {};
struct primary_class {};
struct postfix_class : annotate_position {};
struct power_class : annotate_position {};
struct unary_class : annotate_position {};
struct product_op_class : annotate_position {};
struct product_class : annotate_position {};
struct sum_op_class : annotate_position {};
struct input_class : error_handler {};

inline const x3::rule<number_class, ast::Number> number = "number";
inline const x3::rule<call_class, ast::Call> call = "call";
inline const x3::rule<paren_class, ast::Paren> paren = "parenthesis";
inline const x3::rule<primary_class, ast::Primary> primary = "operand";
inline const x3::rule<postfix_class, ast::Postfix> postfix = "operand";
inline const x3::rule<power_class, ast::Power> power = "operand";
inline const x3::rule<unary_class, ast::Unary> unary = "operand";
inline const x3::rule<product_op_class, ast::ProductOp> product_op = "operand";
inline const x3::rule<product_class, ast::Product> product = "operand";
inline const x3::rule<sum_op_class, ast::SumOp> sum_op = "operand";
/// The entry rule: an expression, with the error handler.
inline const x3::rule<input_class, ast::Expression> input = "expression";

inline const auto digits = +x3::char_("0-9");
inline const auto number_def =
    x3::raw[x3::lexeme[(digits >> -('.' >> *x3::char_("0-9")) | '.' >> digits) >>
                       -(x3::char_("eE") >> -x3::char_("+-") >> digits)]];
inline const auto name_def = x3::raw[x3::lexeme[x3::char_("A-Za-z_") >> *x3::char_("A-Za-z0-9_")]];
inline const auto call_def = (name >> '(') > guarded[expression] > *(',' > guarded[expression]) > ')';
inline const auto paren_def = '(' > guarded[expression] > ')';
inline const auto primary_def = number | call | name | paren;
inline const auto postfix_def = primary >> *x3::char_('\'');
inline const auto power_def = postfix >> -('^' > guarded[unary]);
inline const auto unary_def = *x3::char_('-') >> power;
inline const auto product_op_def = x3::char_("*/") > unary;
// `[unit]`: any text up to `]` on the line; phynjo-lagc's front end reads it
inline const auto unit_def = '[' > x3::lexeme[*(x3::char_ - x3::char_("[]\n"))] > ']';
// a quantity may be a factor: `0.5 [N]*x` (the unit binds to the numbers before it)
inline const auto product_def = unary >> *product_op >> -unit >> *product_op;
// `-` followed by `>` is the arrow of an event statement, not a minus
inline const auto sum_op_def = (x3::char_('+') | (x3::char_('-') >> !x3::lit('>'))) > product;
inline const auto expression_def = product >> *sum_op;
inline const auto input_def = expression;

BOOST_SPIRIT_DEFINE(number, name, call, paren, primary, postfix, power, unary, product_op, product, sum_op, unit,
                    expression, input)

} // namespace phynjo::grammar::parser

#pragma once
// The expression grammar's declarations (the calc9 pattern): what both parsers share — the
// tags of the parse context, the one error handler, the depth guard's counter, position
// annotation, the skipper — and the rules the statement grammar (lag_def.hpp) uses: `name`,
// `unit` and `expression`, declared here, defined in expression_def.hpp and instantiated
// once, in expression.cpp, for the one iterator and context both parsers use.
#include "ast_adapted.hpp"

#include "phynjo/grammar/expression.hpp"

#include <boost/spirit/home/x3.hpp>

#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <type_traits>

namespace phynjo::grammar::parser {

namespace x3 = boost::spirit::x3;

struct position_cache_tag;
struct depth_tag;
struct error_report_tag;

/// The first expectation failure of a parse: where it happened and what X3 expected there
/// (a rule's name or a literal).
struct ExpectationReport {
    const char* where = nullptr;
    std::string which;
};

/// The one X3 error handler of both parsers (the calc9/rexpr pattern): attached to the
/// entry rule of each (`input` here, `statement` in lag_def.hpp), it records the expectation
/// failure for the diagnostic (lexical::report_expected words it) and fails the parse.
struct error_handler {
    template <typename Iterator, typename Exception, typename Context>
    x3::error_handler_result on_error(Iterator&, Iterator const&, Exception const& x, Context const& context) const {
        ExpectationReport& report = x3::get<error_report_tag>(context).get();
        if (!report.where) {
            report.where = std::to_address(x.where());
            report.which = x.which();
        }
        return x3::error_handler_result::fail;
    }
};

/// Thrown when nesting exceeds the limit; carries where.
struct DepthExceeded {
    const char* where;
};

struct DepthCounter {
    std::size_t depth = 0;
    std::size_t limit = 200;
};

/// Records the source range of every position-tagged node.
struct annotate_position {
    template <typename T, typename Iterator, typename Context>
    void on_success(Iterator const& first, Iterator const& last, T& ast, Context const& context) const {
        if constexpr (std::is_base_of_v<x3::position_tagged, T>)
            x3::get<position_cache_tag>(context).get().annotate(ast, first, last);
    }
};

struct name_class : annotate_position {};
struct unit_class : annotate_position {};
struct expression_class : annotate_position {};

using name_type = x3::rule<name_class, ast::Name>;
using unit_type = x3::rule<unit_class, ast::Unit>;
using expression_type = x3::rule<expression_class, ast::Expression>;
inline const name_type name = "name";
inline const unit_type unit = "unit";
inline const expression_type expression = "expression";

/// White space and `#` comments.
inline const auto skipper = x3::char_(" \t\r\n\f\v") | x3::lexeme['#' >> *(x3::char_ - x3::lit('\n'))];

/// What both parsers parse: the text of a Positions.
using iterator_type = std::string_view::const_iterator;
/// The context both parsers parse in: x3::with the error report, the position cache and the
/// depth counter (outermost first, as parse_expression and parse_model build it) around
/// phrase_parse's skipper.
using context_type = x3::context<
    depth_tag, std::reference_wrapper<DepthCounter>,
    x3::context<position_cache_tag, std::reference_wrapper<Positions::Cache>,
                x3::context<error_report_tag, std::reference_wrapper<ExpectationReport>,
                            x3::phrase_parse_context<std::remove_const_t<decltype(skipper)>>::type>>>;

BOOST_SPIRIT_DECLARE(name_type, unit_type, expression_type)

} // namespace phynjo::grammar::parser

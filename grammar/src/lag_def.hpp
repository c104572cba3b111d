#pragma once
// X3 rules of .lag statements (docs/language.md, *Statements*), on the expression rules
// declared in expression_rules.hpp (defined and instantiated in expression.cpp).
// A statement is one logical line (lag.cpp splits the file first: a newline inside open
// parentheses is white space), so the rules see one statement at a time.
#include "expression_rules.hpp"

namespace phynjo::grammar::parser {

/// `kw(word)`: the keyword as a whole word (not the prefix of a longer name).
inline auto kw(const char* word) { return x3::lexeme[x3::lit(word) >> !x3::char_("A-Za-z0-9_")]; }

struct binding_class : annotate_position {};
struct model_stmt_class : annotate_position {};
struct coordinates_stmt_class : annotate_position {};
struct parameters_stmt_class : annotate_position {};
struct let_stmt_class : annotate_position {};
struct lagrangian_stmt_class : annotate_position {};
struct dissipation_stmt_class : annotate_position {};
struct force_stmt_class : annotate_position {};
struct initial_stmt_class : annotate_position {};
struct input_stmt_class : annotate_position {};
struct constraint_stmt_class : annotate_position {};
struct event_action_class : annotate_position {};
struct event_stmt_class : annotate_position {};
struct relation_class {};
struct event_actions_class {};
struct point_class : annotate_position {};
struct sphere_class : annotate_position {};
struct segment_class : annotate_position {};
struct capsule_class : annotate_position {};
struct rotation_class : annotate_position {};
struct rotations_class {};
struct box_class : annotate_position {};
struct geometry_class {};
struct shape_stmt_class : annotate_position {};
struct at_class {};
struct to_class {};
struct from_class {};
struct rotated_class {};
struct about_class {};
struct then_class {};
struct statement_class : error_handler {}; // the entry rule
struct bindings_class {};
struct names_class {};
struct coordinate_decl_class : annotate_position {};

inline const x3::rule<binding_class, ast::Binding> binding = "binding";
inline const x3::rule<model_stmt_class, ast::ModelStmt> model_stmt = "model statement";
inline const x3::rule<coordinates_stmt_class, ast::CoordinatesStmt> coordinates_stmt = "coordinates statement";
inline const x3::rule<parameters_stmt_class, ast::ParametersStmt> parameters_stmt = "parameters statement";
inline const x3::rule<let_stmt_class, ast::LetStmt> let_stmt = "let statement";
inline const x3::rule<lagrangian_stmt_class, ast::LagrangianStmt> lagrangian_stmt = "lagrangian statement";
inline const x3::rule<dissipation_stmt_class, ast::DissipationStmt> dissipation_stmt = "dissipation statement";
inline const x3::rule<force_stmt_class, ast::ForceStmt> force_stmt = "force statement";
inline const x3::rule<initial_stmt_class, ast::InitialStmt> initial_stmt = "initial statement";
inline const x3::rule<input_stmt_class, ast::InputStmt> input_stmt = "input statement";
inline const x3::rule<constraint_stmt_class, ast::ConstraintStmt> constraint_stmt = "constraint statement";
inline const x3::rule<event_action_class, ast::EventAction> event_action = "an action (Q = EXPR, Q' = EXPR or stop)";
inline const x3::rule<event_actions_class, std::vector<ast::EventAction>> event_actions = "an action (Q = EXPR, Q' = EXPR or stop)";
inline const x3::rule<relation_class, char> relation = "'<' or '>'";
inline const x3::rule<event_stmt_class, ast::EventStmt> event_stmt = "event statement";
inline const x3::rule<point_class, ast::Point> point = "a point (X, Y, Z)";
inline const x3::rule<sphere_class, ast::Sphere> sphere = "sphere";
inline const x3::rule<segment_class, ast::Segment> segment = "segment";
inline const x3::rule<capsule_class, ast::Capsule> capsule = "capsule";
inline const x3::rule<rotation_class, ast::Rotation> rotation = "a rotation (ANGLE about (AX, AY, AZ))";
inline const x3::rule<rotations_class, std::vector<ast::Rotation>> rotations = "a rotation (ANGLE about (AX, AY, AZ))";
inline const x3::rule<box_class, ast::Box> box = "box";
inline const x3::rule<geometry_class, ast::Geometry> geometry =
    "a shape (sphere R at (X, Y, Z), segment (X1, Y1, Z1) to (X2, Y2, Z2), capsule R from (X1, Y1, Z1) to (X2, Y2, Z2) or "
    "box (HX, HY, HZ) at (X, Y, Z))";
inline const x3::rule<shape_stmt_class, ast::ShapeStmt> shape_stmt = "shape statement";
inline const x3::rule<at_class> at_kw = "'at'";
inline const x3::rule<to_class> to_kw = "'to'";
inline const x3::rule<from_class> from_kw = "'from'";
inline const x3::rule<rotated_class> rotated_kw = "'rotated'";
inline const x3::rule<about_class> about_kw = "'about'";
inline const x3::rule<then_class> then_kw = "'then'";
inline const x3::rule<statement_class, ast::Statement> statement = "statement";
inline const x3::rule<bindings_class, std::vector<ast::Binding>> bindings = "binding";
inline const x3::rule<names_class, std::vector<ast::CoordinateDecl>> names = "name";
inline const x3::rule<coordinate_decl_class, ast::CoordinateDecl> coordinate_decl = "name";

inline const auto binding_def = name >> *x3::char_('\'') > '=' > expression;
inline const auto bindings_def = binding % ',';
inline const auto coordinate_decl_def = name >> -unit;
inline const auto names_def = coordinate_decl % ',';
inline const auto model_stmt_def = kw("model") > name;
inline const auto coordinates_stmt_def = kw("coordinates") > names;
inline const auto parameters_stmt_def = kw("parameters") > bindings;
inline const auto let_stmt_def = kw("let") > name > -unit > '=' > expression;
inline const auto lagrangian_stmt_def = kw("lagrangian") > expression;
inline const auto dissipation_stmt_def = kw("dissipation") > expression;
inline const auto force_stmt_def = kw("force") > name > '=' > expression;
inline const auto initial_stmt_def = kw("initial") > bindings;
inline const auto input_stmt_def = kw("input") > bindings;
inline const auto constraint_stmt_def = kw("constraint") > name > ':' > expression > '=' > expression;
inline const auto event_action_def = name >> *x3::char_('\'') >> -('=' > expression);
inline const auto event_actions_def = event_action % ',';
inline const auto relation_def = x3::char_("<>");
inline const auto event_stmt_def = kw("event") > name > ':' > expression > relation > expression > "->" > event_actions;
inline const auto point_def = '(' > expression > ',' > expression > ',' > expression > ')';
inline const auto at_kw_def = kw("at");
inline const auto to_kw_def = kw("to");
inline const auto from_kw_def = kw("from");
inline const auto sphere_def = kw("sphere") > expression > at_kw > point;
inline const auto segment_def = kw("segment") > point > to_kw > point;
inline const auto capsule_def = kw("capsule") > expression > from_kw > point > to_kw > point;
inline const auto rotated_kw_def = kw("rotated");
inline const auto about_kw_def = kw("about");
inline const auto then_kw_def = kw("then");
inline const auto rotation_def = expression > about_kw > point;
inline const auto rotations_def = rotation >> *(then_kw > rotation);
inline const auto box_def = kw("box") > point > at_kw > point > -(rotated_kw > rotations);
inline const auto geometry_def = sphere | segment | capsule | box;
inline const auto shape_stmt_def = kw("shape") > name > ':' > geometry;
inline const auto statement_def = model_stmt | coordinates_stmt | parameters_stmt | let_stmt | lagrangian_stmt |
                                  dissipation_stmt | force_stmt | initial_stmt | input_stmt | constraint_stmt | event_stmt |
                                  shape_stmt;

BOOST_SPIRIT_DEFINE(binding, bindings, names, coordinate_decl, model_stmt, coordinates_stmt, parameters_stmt, let_stmt, lagrangian_stmt, dissipation_stmt,
                    force_stmt, initial_stmt, input_stmt, constraint_stmt, event_action, event_actions, relation, event_stmt,
                    point, sphere, segment, capsule, rotation, rotations, box, geometry, shape_stmt, at_kw, to_kw, from_kw,
                    rotated_kw, about_kw, then_kw, statement)

} // namespace phynjo::grammar::parser

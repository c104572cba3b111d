// Golden diagnostics for .lag files: every error class of docs/language.md, exactly as a user
// sees it, several per run where possible.
#include "compiled_model.hpp"

#include "phynjo/cas/cas.hpp"
#include "phynjo/codegen/equations.hpp"
#include "phynjo/grammar/expression.hpp"
#include "phynjo/codegen/frontend.hpp"

#include <catch2/catch.hpp>

namespace {
std::string diagnose(std::string_view text) {
    phynjo::grammar::DiagnosticSink sink("m.lag", text);
    auto model = phynjo::codegen::read_model(text, "m.lag", sink);
    if (model) (void)phynjo::codegen::derive(*model, sink);
    return sink.error_count() ? sink.format_all() : "(accepted)";
}
const char* ok_tail = "coordinates q\nlagrangian 1/2*q'^2 - 1/2*q^2\n";
} // namespace

TEST_CASE("lag diagnostics: names", "[codegen][diagnostics]") {
    CHECK(diagnose("coordinates q\nlagrangian 1/2*m*q'^2\n") ==
          "m.lag:2:16: error: unknown name 'm'\n    lagrangian 1/2*m*q'^2\n                   ^\n");
    CHECK(diagnose("coordinates q, q\nlagrangian q'^2\n") ==
          "m.lag:1:16: error: 'q' is already declared\n    coordinates q, q\n                   ^\n"
          "m.lag:1:13: note: the first declaration of 'q' is here\n    coordinates q, q\n                ^\n");
    CHECK(diagnose("coordinates q\nparameters q = 1\nlagrangian q'^2\n") ==
          "m.lag:2:12: error: 'q' is already declared\n    parameters q = 1\n               ^\n"
          "m.lag:1:13: note: the first declaration of 'q' is here\n    coordinates q\n                ^\n");
    CHECK(diagnose("coordinates t\nlagrangian 1\n") ==
          "m.lag:1:13: error: 't' is a built-in name and cannot be declared\n    coordinates t\n                ^\n");
    CHECK(diagnose("coordinates q\nlet sin = 2\nlagrangian q'^2\n") ==
          "m.lag:2:5: error: 'sin' is a built-in name and cannot be declared\n    let sin = 2\n        ^~~\n");
    CHECK(diagnose("coordinates q, lagrangian\nlagrangian q'^2\n") ==
          "m.lag:1:16: error: 'lagrangian' is a keyword and cannot be declared\n    coordinates q, lagrangian\n"
          "                   ^~~~~~~~~~\n");
    CHECK(diagnose("coordinates q\nparameters class = 1\nlagrangian q'^2\n") ==
          "m.lag:2:12: error: 'class' cannot name a parameter: it is a C++ keyword, and parameters become fields of the "
          "generated Parameters struct\n    parameters class = 1\n               ^~~~~\n");
    CHECK(diagnose("let x = y\ncoordinates q\nlagrangian q'^2\n") ==
          "m.lag:1:9: error: unknown name 'y'\n    let x = y\n            ^\n");
    // declared after use
    CHECK(diagnose("coordinates q\nlagrangian k*q'^2\nparameters k = 2\n") ==
          "m.lag:2:12: error: unknown name 'k'\n    lagrangian k*q'^2\n               ^\n");
}

TEST_CASE("lag diagnostics: missing and repeated statements", "[codegen][diagnostics]") {
    CHECK(diagnose("coordinates q\n") == "m.lag:1:1: error: the model has no 'lagrangian' statement\n    coordinates q\n    ^\n");
    CHECK(diagnose("lagrangian 1\n") == "m.lag:1:1: error: the model has no 'coordinates' statement\n    lagrangian 1\n    ^\n");
    CHECK(diagnose("") == "m.lag:1:1: error: the model file is empty\n    \n    ^\n");
    CHECK(diagnose("  \n\n") == "m.lag:1:1: error: the model file is empty\n      \n    ^\n");
    CHECK(diagnose(std::string(ok_tail) + "lagrangian q'^2\n") ==
          "m.lag:3:1: error: a second 'lagrangian' statement\n    lagrangian q'^2\n    ^~~~~~~~~~~~~~~\n"
          "m.lag:2:1: note: the first 'lagrangian' statement is here\n    lagrangian 1/2*q'^2 - 1/2*q^2\n    ^~~~~~~~~~~~~~~~~~~~~~~~~~~~~\n");
}

TEST_CASE("lag diagnostics: derivatives and constants", "[codegen][diagnostics]") {
    CHECK(diagnose("coordinates q\nlagrangian q''^2\n") ==
          "m.lag:2:12: error: second derivative: q'' is not allowed in a model (the equations of motion are derived from L)\n"
          "    lagrangian q''^2\n               ^~~\n");
    CHECK(diagnose("coordinates q\nlet v = q'\nlagrangian v'^2\n") == // v' is q''
          "m.lag:3:12: error: second derivative: q'' is not allowed in a model (the equations of motion are derived from L)\n"
          "    lagrangian v'^2\n               ^~\n");
    CHECK(diagnose("coordinates q\nlet v = q*q'\nlagrangian v'^2\n") ==
          "m.lag:3:12: error: second derivative: ' applied to an expression that contains the velocity q'\n"
          "    lagrangian v'^2\n               ^~\n");
    // a total derivative of a parenthesised expression, and a parenthesised velocity: valid
    CHECK(diagnose("coordinates q\nlagrangian (q*sin(q))'^2 + (q')^2\n") == "(accepted)");
    CHECK(diagnose("coordinates q\nparameters k = 2*q\nlagrangian q'^2\n") ==
          "m.lag:2:16: error: the value of parameter 'k' is not constant: it depends on the coordinate q\n"
          "    parameters k = 2*q\n                   ^~~\n");
    CHECK(diagnose("coordinates q\nparameters k = t\nlagrangian q'^2\n") ==
          "m.lag:2:16: error: the value of parameter 'k' is not constant: it depends on time t\n"
          "    parameters k = t\n                   ^\n");
    CHECK(diagnose("parameters a = 2, b = a^2 + pi\ncoordinates q\nlagrangian b*q'^2\n") == "(accepted)");
    CHECK(diagnose("coordinates q\nparameters k = log(0)\nlagrangian q'^2\n") ==
          "m.lag:2:16: error: log(0) is undefined\n    parameters k = log(0)\n                   ^~~~~~\n");
    CHECK(diagnose("coordinates q\ninitial q = q\nlagrangian q'^2\n") ==
          "m.lag:2:13: error: the initial value of q is not constant: it depends on the coordinate q\n"
          "    initial q = q\n                ^\n");
}

TEST_CASE("lag diagnostics: forces, initial values, singular mass matrices", "[codegen][diagnostics]") {
    CHECK(diagnose("coordinates q\nparameters m = 1\nforce m = 2\nlagrangian q'^2\n") ==
          "m.lag:3:7: error: force on 'm', which is not a coordinate\n    force m = 2\n          ^\n");
    CHECK(diagnose("coordinates q\nforce q = 1\nforce q = 2\nlagrangian q'^2\n") ==
          "m.lag:3:7: error: a second force on 'q'\n    force q = 2\n          ^\n");
    CHECK(diagnose("coordinates q\ninitial x = 1\nlagrangian q'^2\n") ==
          "m.lag:2:9: error: unknown name 'x'\n    initial x = 1\n            ^\n");
    CHECK(diagnose("coordinates x, y\nlagrangian 1/2*x'^2 - y^2\n") ==
          "m.lag:1:16: error: the mass matrix is singular for every state: the equations of motion cannot be solved for "
          "y'' (y' does not appear in the Lagrangian)\n    coordinates x, y\n                   ^\n");
    CHECK(diagnose("coordinates a, b\nlagrangian 1/2*(a' + b')^2 - a^2 - b^2\n") ==
          "m.lag:1:16: error: the mass matrix is singular for every state: the equations of motion cannot be solved for "
          "b''\n    coordinates a, b\n                   ^\n");
}

TEST_CASE("lag diagnostics: syntax, file-level problems, several errors per run", "[codegen][diagnostics]") {
    // one mistake, one error: a lagrangian statement with a syntax error is not also missing
    CHECK(diagnose("coordinates q\nlagrangian (q'^2\n") ==
          "m.lag:2:12: error: '(' is never closed\n    lagrangian (q'^2\n               ^\n");
    CHECK(diagnose("coordinates q\nlagrangian q'^2)\n") ==
          "m.lag:2:16: error: unmatched ')'\n    lagrangian q'^2)\n                   ^\n");
    CHECK(diagnose("coordinates q\nlagrangain q'^2\n") ==
          "m.lag:2:1: error: expected a statement (model, coordinates, parameters, let, lagrangian, dissipation, force, "
          "initial, input, constraint, event or shape), found 'lagrangain' (did you mean 'lagrangian'?)\n    lagrangain q'^2\n    ^~~~~~~~~~\n");
    CHECK(diagnose("coordinates q\nlagrangian 1/2*q'^2 +\n") ==
          "m.lag:2:22: error: expected an expression, found end of line\n    lagrangian 1/2*q'^2 +\n                         ^\n");
    CHECK(diagnose(std::string("coordinates q\nlagrangian q'^2 \xff\n")) ==
          "m.lag:2:17: error: not UTF-8 text: invalid byte 0xFF\n    lagrangian q'^2 \xff\n                    ^\n");
    CHECK(diagnose(std::string(17u << 20, ' ')).rfind("m.lag:1:1: error: file too large (17825792 bytes; the limit is 16777216)", 0) == 0);
    // wrapped in parentheses, a statement may span lines; a comment may follow
    CHECK(diagnose("coordinates q   # the angle\nlagrangian (1/2*q'^2\n   - 1/2*q^2)\n") == "(accepted)");
    // three independent mistakes, three diagnostics
    const std::string three = diagnose("coordinates q\nparameters k = q\nlet a = b\nlagrangian q'^2 + c\n");
    CHECK(three.find("m.lag:2:16: error: the value of parameter 'k' is not constant") != std::string::npos);
    CHECK(three.find("m.lag:3:9: error: unknown name 'b'") != std::string::npos);
    CHECK(three.find("m.lag:4:19: error: unknown name 'c'") != std::string::npos);
}

// The newcomer's diagnostics (issue: never a C++ type name, one mistake one error, a
// non-ASCII character named by itself, the hint for a statement broken over two lines).
TEST_CASE("lag diagnostics: what a first-time user writes", "[codegen][diagnostics]") {
    // a parameter without a value: no Spirit type name, and 'm' is not also "unknown"
    CHECK(diagnose("coordinates x\nparameters m, k = 2\nlagrangian 1/2*m*x'^2\n") ==
          "m.lag:2:13: error: expected '=' and a value after parameter 'm', found ','\n    parameters m, k = 2\n"
          "                ^\n");
    CHECK(diagnose("coordinates x\nparameters k = 2, m\nlagrangian 1/2*m*x'^2\n") ==
          "m.lag:2:20: error: expected '=' and a value after parameter 'm'\n    parameters k = 2, m\n"
          "                       ^\n");
    CHECK(diagnose("coordinates x\nlagrangian 1/2*x'^2\ninitial x 1\n") ==
          "m.lag:3:11: error: expected '=' and a value after initial value of 'x', found '1'\n    initial x 1\n"
          "              ^\n");
    // a statement continued on the next line without parentheses: one error, with the remedy
    CHECK(diagnose("coordinates x\nlagrangian 1/2*x'^2 -\n    1/2*x^2\n") ==
          "m.lag:2:22: error: expected an expression, found end of line (a statement goes on to the next line only "
          "inside parentheses: wrap it in ( ) )\n    lagrangian 1/2*x'^2 -\n                         ^\n");
    // a Greek letter names itself and says what names are
    CHECK(diagnose("coordinates θ\nlagrangian 1/2*θ'^2\n") ==
          "m.lag:1:13: error: unexpected character 'θ' (U+03B8): names are ASCII letters, digits and _\n"
          "    coordinates θ\n                ^\n"
          "m.lag:2:16: error: unexpected character 'θ' (U+03B8): names are ASCII letters, digits and _\n"
          "    lagrangian 1/2*θ'^2\n                   ^\n");
    // no message ever carries a C++ type name
    for (const char* text : {"coordinates\nlagrangian 1\n", "parameters\ncoordinates q\nlagrangian q'^2\n",
                             "coordinates q\ninitial\nlagrangian q'^2\n", "coordinates q,\nlagrangian q'^2\n",
                             "coordinates q\nparameters a = 1,\nlagrangian q'^2\n", "model\ncoordinates q\nlagrangian q'^2\n"}) {
        const std::string d = diagnose(text);
        INFO(text << " -> " << d);
        CHECK(d.find("boost") == std::string::npos);
        CHECK(d.find("error:") != std::string::npos);
    }
}

// Bug caught: a constraint mistake that crashes, passes silently, or is reported without
// its place and the earlier constraint it clashes with.
TEST_CASE("lag diagnostics: constraints and inputs, with notes", "[codegen][diagnostics][constraints]") {
    CHECK(diagnose("coordinates x, y\nlagrangian 1/2*(x'^2 + y'^2)\nconstraint rod: x^2 + y^2 = 1\n"
                   "constraint again: 3*x^2 + 3*y^2 = 3\n") ==
          "m.lag:4:12: error: constraint 'again' repeats constraint 'rod' (its residual is a constant multiple of that "
          "one's): remove one of them\n"
          "    constraint again: 3*x^2 + 3*y^2 = 3\n               ^~~~~\n"
          "m.lag:3:12: note: constraint 'rod' is here\n    constraint rod: x^2 + y^2 = 1\n               ^~~\n");
    CHECK(diagnose("coordinates x, y\nlagrangian 1/2*(x'^2 + y'^2)\nconstraint c: x = 1\nconstraint c: y = 1\n") ==
          "m.lag:4:12: error: a second constraint named 'c'\n    constraint c: y = 1\n               ^\n"
          "m.lag:3:12: note: the first constraint 'c' is here\n    constraint c: x = 1\n               ^\n");
    CHECK(diagnose("coordinates x, y\nlagrangian 1/2*(x'^2 + y'^2)\nconstraint skate: x'*y' = 0\n") ==
          "m.lag:3:12: error: constraint 'skate' is not linear in the velocities: x' enters nonlinearly (a nonholonomic "
          "constraint must be a(q, t)*q' + b(q, t) = 0)\n    constraint skate: x'*y' = 0\n               ^~~~~\n");
    // one mistake, one error: a parameter whose value is rejected is not also unknown where it is used
    CHECK(diagnose("coordinates x\ninput u = 1\nparameters k = 2*u\nlagrangian 1/2*x'^2 - 1/2*k*x^2\n") ==
          "m.lag:3:16: error: the value of parameter 'k' is not constant: it depends on the input u (inputs change "
          "during a run)\n    parameters k = 2*u\n                   ^~~\n");
    // accepted: holonomic, rheonomic and nonholonomic constraints, and an input in a force
    CHECK(diagnose("coordinates x, y\ninput u = 0.5\nlagrangian 1/2*(x'^2 + y'^2)\nforce x = u\n"
                   "constraint a: x = sin(t)\nconstraint b: x' + t*y' = 0\n") == "(accepted)");
}

// Bugs caught: events accepted with a constant guard, a reset of a parameter, `stop` mixed
// with resets; a reset written twice without the note to the first; a syntax error in an
// event reported in X3's words; several mistakes in one event reported one by one.
TEST_CASE("lag diagnostics: events, with notes", "[codegen][diagnostics][events]") {
    CHECK(diagnose("coordinates x\nlagrangian 1/2*x'^2\nevent e: x < 0 -> x' = 0, x' = 1\n") ==
          "m.lag:3:27: error: event 'e' resets x' twice\n    event e: x < 0 -> x' = 0, x' = 1\n                              ^\n"
          "m.lag:3:19: note: the first reset of x' is here\n    event e: x < 0 -> x' = 0, x' = 1\n                      ^\n");
    CHECK(diagnose("coordinates x\nparameters m = 1\nlagrangian 1/2*x'^2\nevent e: m < 1 -> m = 2, stop\n") ==
          "m.lag:4:10: error: the guard of event 'e' is constant: m - 1 depends on no coordinate, velocity, input or t, "
          "so it never crosses zero\n    event e: m < 1 -> m = 2, stop\n             ^~\n"
          "m.lag:4:19: error: event 'e' resets 'm', which is not a coordinate\n    event e: m < 1 -> m = 2, stop\n"
          "                      ^\n");
    CHECK(diagnose("coordinates x\nlagrangian 1/2*x'^2\nevent e: x = 0 -> stop\n") ==
          "m.lag:3:12: error: expected '<' or '>', found '='\n    event e: x = 0 -> stop\n               ^\n");
    CHECK(diagnose("coordinates x\nlagrangian 1/2*x'^2\nevent e: x < 0 -> x' = -x', stop\n") ==
          "m.lag:3:29: error: event 'e' mixes 'stop' with resets: a run that stops at the event never uses the reset "
          "state (write two events, or drop the resets)\n    event e: x < 0 -> x' = -x', stop\n                                ^~~~\n");
    // accepted: `<` and `>`, guards on t, velocities and inputs, resets of both kinds, stop,
    // and `->` right after an expression ending in a name (not a minus)
    CHECK(diagnose("coordinates x, y\ninput u = 0\nlagrangian 1/2*(x'^2 + y'^2)\nevent a: x < -1 -> x' = -x', y = 0\n"
                   "event b: y' > u -> stop\nevent c: t > 2->stop\n") == "(accepted)");
}


// Bugs caught: a negative or non-constant radius accepted, a shape that moves with a
// velocity, a missing 'at'/'to'/'from'/'about' reported in X3's words, a zero or turning box
// axis, a second shape of a name without
// the note to the first, a centre that is not a length in a file with units.
TEST_CASE("lag diagnostics: shapes", "[codegen][diagnostics][shapes]") {
    CHECK(diagnose("coordinates x\nparameters r = -1/10\nlagrangian 1/2*x'^2\nshape b: sphere r at (x, 0, 0)\n") ==
          "m.lag:4:17: error: the radius of shape 'b' is r = -1/10 at the parameters' defaults: a radius must be a "
          "positive finite length\n    shape b: sphere r at (x, 0, 0)\n                    ^~\n");
    CHECK(diagnose("coordinates x\ninput u = 1\nlagrangian 1/2*x'^2\nshape b: sphere u at (x, 0, 0)\n") ==
          "m.lag:4:17: error: the radius of shape 'b' is not constant: it depends on the input u (inputs change during "
          "a run)\n    shape b: sphere u at (x, 0, 0)\n                    ^~\n");
    CHECK(diagnose("coordinates x\nlagrangian 1/2*x'^2\nshape b: sphere 1 at (x', 0, 0)\n") ==
          "m.lag:3:23: error: the centre of shape 'b' depends on the velocity x': a shape's position may depend on t, "
          "coordinates, parameters and inputs\n    shape b: sphere 1 at (x', 0, 0)\n                          ^~\n");
    CHECK(diagnose("coordinates x\nlagrangian 1/2*x'^2\nshape s: segment (0, 0, 0) (x, 0, 0)\n") ==
          "m.lag:3:28: error: expected 'to', found '('\n    shape s: segment (0, 0, 0) (x, 0, 0)\n"
          "                               ^\n");
    CHECK(diagnose("coordinates x\nlagrangian 1/2*x'^2\nshape s: cone 1 at (x, 0, 0)\n") ==
          "m.lag:3:10: error: expected a shape (sphere R at (X, Y, Z), segment (X1, Y1, Z1) to (X2, Y2, Z2), capsule R "
          "from (X1, Y1, Z1) to (X2, Y2, Z2) or box (HX, HY, HZ) at (X, Y, Z)), found 'cone'\n"
          "    shape s: cone 1 at (x, 0, 0)\n             ^~~~\n");
    // boxes: three half extents, 'at', 'about' after each angle, something after 'then'; half
    // extents like radii; a constant, non-zero axis; angles without velocities
    const std::string box = "coordinates x\nlagrangian 1/2*x'^2\nshape s: box ";
    CHECK(diagnose(box + "1 at (x, 0, 0)\n") ==
          "m.lag:3:14: error: expected a point (X, Y, Z), found '1'\n    shape s: box 1 at (x, 0, 0)\n                 ^\n");
    CHECK(diagnose(box + "(1, 1, 1)\n") ==
          "m.lag:3:23: error: expected 'at', found end of line\n    shape s: box (1, 1, 1)\n                          ^\n");
    CHECK(diagnose(box + "(1, 1, 1) at (x, 0, 0) rotated x\n") ==
          "m.lag:3:46: error: expected 'about', found end of line\n    shape s: box (1, 1, 1) at (x, 0, 0) rotated x\n"
          "                                                 ^\n");
    CHECK(diagnose(box + "(1, 1, 1) at (x, 0, 0) rotated x about (0, 0, 1) then\n") ==
          "m.lag:3:67: error: expected a rotation (ANGLE about (AX, AY, AZ)), found end of line\n"
          "    shape s: box (1, 1, 1) at (x, 0, 0) rotated x about (0, 0, 1) then\n"
          "                                                                      ^\n");
    CHECK(diagnose(box + "(1/2, 1, -1) at (x, 0, 0)\n") ==
          "m.lag:3:23: error: the half extent along z of shape 's' is -1: a half extent must be a positive finite length\n"
          "    shape s: box (1/2, 1, -1) at (x, 0, 0)\n                          ^~\n");
    CHECK(diagnose(box + "(1, 1, 1) at (x, 0, 0) rotated x about (0, 0, 0)\n") ==
          "m.lag:3:53: error: the axis of the rotation of shape 's' is (0, 0, 0): an axis must have a positive finite length\n"
          "    shape s: box (1, 1, 1) at (x, 0, 0) rotated x about (0, 0, 0)\n"
          "                                                        ^~~~~~~~~\n");
    CHECK(diagnose(box + "(1, 1, 1) at (x, 0, 0) rotated x about (0, 0, 1) then x about (x, 0, 1)\n") ==
          "m.lag:3:77: error: the axis of the rotation 2 of shape 's' is not constant: it depends on the coordinate x\n"
          "    shape s: box (1, 1, 1) at (x, 0, 0) rotated x about (0, 0, 1) then x about (x, 0, 1)\n"
          "                                                                                ^\n");
    CHECK(diagnose(box + "(1, 1, 1) at (x, 0, 0) rotated x' about (0, 0, 1)\n") ==
          "m.lag:3:45: error: the angle of the rotation of shape 's' depends on the velocity x': a shape's position may "
          "depend on t, coordinates, parameters and inputs\n    shape s: box (1, 1, 1) at (x, 0, 0) rotated x' about (0, 0, 1)\n"
          "                                                ^~~\n");
    // capsules: 'from' and 'to' in their places, a radius like a sphere's, ends without velocities
    CHECK(diagnose("coordinates x\nlagrangian 1/2*x'^2\nshape c: capsule 1 (0, 0, 0) to (x, 0, 0)\n") ==
          "m.lag:3:20: error: expected 'from', found '('\n    shape c: capsule 1 (0, 0, 0) to (x, 0, 0)\n"
          "                       ^\n");
    CHECK(diagnose("coordinates x\nlagrangian 1/2*x'^2\nshape c: capsule 1 from (0, 0, 0) (x, 0, 0)\n") ==
          "m.lag:3:35: error: expected 'to', found '('\n    shape c: capsule 1 from (0, 0, 0) (x, 0, 0)\n"
          "                                      ^\n");
    CHECK(diagnose("coordinates x\nlagrangian 1/2*x'^2\nshape c: capsule 0 from (0, 0, 0) to (x, 0, 0)\n") ==
          "m.lag:3:18: error: the radius of shape 'c' is 0: a radius must be a positive finite length\n"
          "    shape c: capsule 0 from (0, 0, 0) to (x, 0, 0)\n                     ^~\n");
    CHECK(diagnose("coordinates x\nlagrangian 1/2*x'^2\nshape c: capsule 1 from (0, 0, 0) to (x, x', 0)\n") ==
          "m.lag:3:42: error: the second end of shape 'c' depends on the velocity x': a shape's position may depend on "
          "t, coordinates, parameters and inputs\n    shape c: capsule 1 from (0, 0, 0) to (x, x', 0)\n"
          "                                             ^~\n");
    CHECK(diagnose("coordinates x\nlagrangian 1/2*x'^2\nshape s: sphere 1 at (x, 0, 0)\nshape s: sphere 2 at (0, x, 0)\n") ==
          "m.lag:4:7: error: a second shape named 's'\n    shape s: sphere 2 at (0, x, 0)\n          ^\n"
          "m.lag:3:7: note: the first shape 's' is here\n    shape s: sphere 1 at (x, 0, 0)\n          ^\n");
    CHECK(diagnose("coordinates x [m]\nparameters m = 1 [kg]\nlagrangian 1/2*m*x'^2\nshape s: sphere 1 [m] at (x, m, 0)\n") ==
          "m.lag:4:30: error: the centre of shape 's': expected m, found kg\n    shape s: sphere 1 [m] at (x, m, 0)\n"
          "                                 ^\n");
    // accepted: a fixed obstacle (no coordinate), t and inputs in a position, a radius from
    // parameters, segments
    CHECK(diagnose("coordinates x\nparameters r = 1/10\ninput u = 0\nlagrangian 1/2*x'^2\nshape wall: sphere 1 at (5, 0, 0)\n"
                   "shape b: sphere 2*r at (x + u, sin(t), 0)\nshape rod: segment (0, 0, 0) to (x, 0, 0)\n"
                   "shape arm: capsule r from (0, 0, 0) to (x, 0, 0)\n") == "(accepted)");
    // 'from', like 'at' and 'to', is a keyword only inside its statement: a parameter may be named so
    CHECK(diagnose("coordinates x\nparameters from = 1/10\nlagrangian 1/2*x'^2\n"
                   "shape arm: capsule from from (0, 0, 0) to (x, from, 0)\n") == "(accepted)");
    // so are 'rotated', 'about' and 'then'; a box with no turn, one turn, two turns
    CHECK(diagnose("coordinates x\nparameters about = 1, then = 2, rotated = 3\nlagrangian 1/2*x'^2\n"
                   "shape s: box (about, then, rotated) at (x, 0, 0) rotated rotated*x about (about, then, 0) then then "
                   "about (0, 0, about)\nshape c: box (1, 1, 1) at (x, 1, 1)\n"
                   "shape d: box (1, 1, 1) at (0, 0, 0) rotated x about (1, 1, 0)\n") == "(accepted)");
}

// Bugs caught: a dimension check that stops at the first error of a file, misses a term of
// L, reads `1/2 [N/m]` as 1/(2 N/m), points at the whole statement instead of the term,
// names the wrong dimension, or checks files without units (a file without units must compile as it is).
TEST_CASE("lag diagnostics: units and dimensions", "[codegen][diagnostics][units]") {
    CHECK(diagnose("coordinates x [m]\nparameters m = 2 [kg], k = 1/2 [N/m]\nlagrangian 1/2*m*x'^2 - 1/2*k*x^2 - m*x\n") ==
          "m.lag:3:37: error: a term of the Lagrangian is not an energy: expected J = kg*m^2/s^2, found kg*m\n"
          "    lagrangian 1/2*m*x'^2 - 1/2*k*x^2 - m*x\n                                        ^~~\n");
    CHECK(diagnose("coordinates x [m]\nparameters m = 2 [kg], k = 1/2 [N/m]\nlagrangian 1/2*m*x'^2 - 1/2*k*(x^2 + x)\n") ==
          "m.lag:3:38: error: '+' joins terms of different dimensions: m^2 and m\n"
          "    lagrangian 1/2*m*x'^2 - 1/2*k*(x^2 + x)\n                                         ^\n");
    CHECK(diagnose("coordinates x [m]\nparameters m = 2 [kg/]\nlagrangian 1/2*m*x'^2\n") ==
          "m.lag:2:22: error: expected a unit name after '/'\n    parameters m = 2 [kg/]\n                         ^\n");
    // accepted: derived units, 1/s, fractional powers through sqrt, 0 without a unit, rad,
    // t in seconds, a parameter defined from others taking their dimension
    CHECK(diagnose("coordinates x [m], th [rad]\n"
                   "parameters m = 2 [kg], k = 8 [N/m], w = sqrt(k/m), P = 3 [W], f = 2 [Hz], I = 1/2*m*(1/10 [m])^2\n"
                   "lagrangian 1/2*m*x'^2 - 1/2*k*x^2 + 1/2*I*th'^2 + P*t*cos(w*t) + 0*x\n"
                   "dissipation P*sin(2*pi*f*t)\nforce x = 0\ninitial x = 1/10 [m], th' = 2 [1/s]\n") == "(accepted)");
    // a file without units: nothing is checked (this L is no energy, and that is fine)
    CHECK(diagnose("coordinates x\nlagrangian x'^2 + x\n") == "(accepted)");
    // a quantity as a factor (`0.5 [N]*x`): accepted, its dimension checked as a product's
    // (a force times a squared length is no energy), its value the quantity times the rest:
    // L = m x'²/2 − x²/2 gives f = −x, and the force −0.1 x'
    CHECK(diagnose("coordinates x [m], th [rad]\nparameters m = 2 [kg]\n"
                   "lagrangian 1/2*m*x'^2 - 1/2 [N/m]*x^2 + 1/2 [kg*m^2]*th'^2 - 3 [N]*(1/10 [m])*cos(th)\n"
                   "force x = -0.1 [N*s/m]*x' + 0.1 [N]*sin(th)\n") == "(accepted)");
    CHECK(diagnose("coordinates x [m]\nparameters m = 2 [kg]\nlagrangian 1/2*m*x'^2 - 0.5 [N]*x^2\n") ==
          "m.lag:3:25: error: a term of the Lagrangian is not an energy: expected J = kg*m^2/s^2, found kg*m^3/s^2\n"
          "    lagrangian 1/2*m*x'^2 - 0.5 [N]*x^2\n                            ^~~~~~~~~~~\n");
    const auto c = phynjo::test::compile_model("coordinates x [m]\nparameters m = 2 [kg]\n"
                                               "lagrangian 1/2*m*x'^2 - 1/2 [N/m]*x^2\nforce x = -0.1 [N*s/m]*x'\n");
    CHECK(phynjo::cas::simplify(c.eom.forcing[0] - phynjo::grammar::parse("-x - 1/10*x'")).is_zero());
}

// Bugs caught: a unit's negative exponent read with the wrong sign (`s^-2` as s²), `a/b/c` read
// as a/(b/c), a derived unit with a wrong definition, blanks inside a unit not skipped. The
// oracle: each unit form the docs allow, as a parameter standing alone as a term of L, is
// reported with its dimension in SI base units (kg m s A K mol cd, in that order; a derived
// unit's name first when one has that dimension), written out by hand here from the SI
// definitions (N = kg·m/s², Pa = N/m², J = N·m, W = J/s, C = A·s, V = W/A, T = V·s/m², Hz = 1/s).
TEST_CASE("lag diagnostics: every unit form against its SI dimension", "[codegen][diagnostics][units]") {
    const char* forms[][2] = {
        {"m*s^-2", "m/s^2"},          {"s^-2", "1/s^2"},           {"m*s^-1", "m/s"},
        {"kg*m^-3", "kg/m^3"},        {"m/s/s", "m/s^2"},          {"1/s", "Hz = 1/s"},
        {"kg * m ^ 2", "kg*m^2"},     {"N/m", "kg/s^2"},           {"N*s/m", "kg/s"},
        {"Hz", "Hz = 1/s"},           {"N", "N = kg*m/s^2"},       {"Pa", "Pa = kg/(m*s^2)"},
        {"W", "W = kg*m^2/s^3"},      {"C", "C = s*A"},            {"V", "V = kg*m^2/(s^3*A)"},
        {"T", "T = kg/(s^2*A)"},      {"mol*K^-1", "mol/K"},       {"cd", "cd"},
        {"kg^-1*m^-2*s^2", "s^2/(kg*m^2)"}, {"rad/s", "Hz = 1/s"},
    };
    for (const auto& [unit, dim] : forms) {
        const std::string text = std::string("coordinates x [m]\nparameters p = 3 [") + unit +
                                 "]\nlagrangian 1/2*1 [kg]*x'^2 + p\n";
        const std::string got = diagnose(text);
        INFO(unit << ": " << got);
        CHECK(got.find(std::string("expected J = kg*m^2/s^2, found ") + dim + "\n") != std::string::npos);
    }
    // the energies, however written, are accepted
    for (const char* unit : {"J", "N*m", "W*s", "Pa*m^3", "kg*m^2*s^-2", "kg*m^2/s/s", "V*A*s", "C*V"}) {
        INFO(unit);
        CHECK(diagnose(std::string("coordinates x [m]\nparameters p = 3 [") + unit +
                       "]\nlagrangian 1/2*1 [kg]*x'^2 + p\n") == "(accepted)");
    }
}

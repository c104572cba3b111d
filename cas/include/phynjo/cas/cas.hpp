#pragma once
/// \file
/// Everything of phynjo::cas.
#include "phynjo/cas/cse.hpp"
#include "phynjo/cas/diff.hpp"
#include "phynjo/cas/errors.hpp"
#include "phynjo/cas/evaluate.hpp"
#include "phynjo/cas/expr.hpp"
#include "phynjo/cas/pool.hpp"
#include "phynjo/cas/print.hpp"
#include "phynjo/cas/rational.hpp"
#include "phynjo/cas/transform.hpp"

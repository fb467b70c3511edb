#pragma once
// A deliberate upward include, for packaging_layers_checker_fails: check_layers.cmake must name
// this file and line 5. Comment lines such as // #include <vplkit/builders/x.hpp> do not count.
#include <vplkit/core/vector.hpp>
#include <vplkit/estimators/vpl_sum.hpp>

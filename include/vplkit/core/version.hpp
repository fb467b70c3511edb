// SPDX-License-Identifier: MIT
#pragma once

// vplkit is C++17 (inline variables, if constexpr, std::data). Say so before anything else fails.
// MSVC reports __cplusplus as 199711L unless /Zc:__cplusplus is given; _MSVC_LANG is reliable.
#if (defined(_MSVC_LANG) ? _MSVC_LANG : __cplusplus) < 201703L
#error "vplkit needs C++17 or later: compile with -std=c++17 (or /std:c++17), or link the CMake target vplkit::vplkit, which asks for cxx_std_17"
#endif

#define VPLKIT_VERSION_MAJOR 0
#define VPLKIT_VERSION_MINOR 1
#define VPLKIT_VERSION_PATCH 0

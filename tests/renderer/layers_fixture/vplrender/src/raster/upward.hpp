// SPDX-License-Identifier: MIT
// A raster file that reaches up into render/: check_renderer_layers.cmake must reject it.
#include "render/settings.hpp"

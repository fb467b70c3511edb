// SPDX-License-Identifier: MIT
// The pattern glsl_restrict_arguments.cmake must find (its test expects the lint to fail here).
struct record { vec4 a; uvec4 b; };
layout(std430, binding = 0) restrict readonly buffer Records { record records[]; };
float first(record r) { return r.a.x; }
layout(local_size_x = 1) in;
void main() { float x = first(records[gl_GlobalInvocationID.x]); }

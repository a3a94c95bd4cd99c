#version 450
// STSV pass: the geometry shader (stsv.geom) reads the triangle by gl_PrimitiveIDIn; the
// vertex stage only feeds it one primitive per scene triangle (3 vertices each, no inputs).
void main() { gl_Position = vec4(0.0, 0.0, 0.0, 1.0); }

// STSV extrusion (STSV paper §2.2–2.3, §4.2; DESIGN §4.2), by concept: one volume's planes, strip
// and point test (volumes/volume_dh.h), the triangle's light planes for a light in a fixed square
// (volumes/light_planes_dh.h), and the hull a volume pass rasterises (volumes/hull_setup_dh.h).
// Compiles as C++ and as GLSL 4.50 (core/dh.h).
#ifndef STSV_VOLUMES_EXTRUSION_DH_H
#define STSV_VOLUMES_EXTRUSION_DH_H

#include "volumes/hull_setup_dh.h"
#include "volumes/light_planes_dh.h"
#include "volumes/volume_dh.h"

#endif // STSV_VOLUMES_EXTRUSION_DH_H

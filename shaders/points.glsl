// Point attributes of the depth pass (render/point_buffer.h): world position, world normal
// (zero when absent) and splat radius in world units.
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in float a_radius;

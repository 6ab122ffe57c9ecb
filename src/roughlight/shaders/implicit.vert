#version 330 core
// One flat quad. In a sweep (field_size = 0) the quad covers the framebuffer
// and every pixel is one sample of one view (implicit.frag). In a scene the
// quad is the base plane z = 0 of an N x N field of periods, placed by the
// orthographic camera `camera` (world -> clip), and each fragment carries its
// point of the base plane in periods.

layout(location = 0) in vec3 position;

uniform mat4 camera;      // world -> clip (scene); identity (sweep: position is in NDC)

out vec2 field_pos;       // the fragment's point of the base plane z = 0, periods

void main()
{
    gl_Position = camera * vec4(position, 1.0);
    field_pos = position.xy;
}

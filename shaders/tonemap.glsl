// Shared by the tone-map shaders: Rec. 709 luminance of linear RGB (LEC19 eq. 8).
float Luminance(vec3 rgb) { return dot(rgb, vec3(0.2126, 0.7152, 0.0722)); }

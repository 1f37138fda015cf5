// A triangle over the whole view (gl_daylight.cpp). (The renderer prepends "#version 330 core".)
layout(location = 0) in vec3 position;
void main() { gl_Position = vec4(position.xy, 0.9999, 1.0); }

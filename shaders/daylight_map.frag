// (The renderer prepends "#version 330 core".) Depth and stencil only, the colour masked: the
// view's depth pre-passes and the photo tiles an object's shadow may reach (gl_daylight.cpp).
out vec4 colour;
void main() {
  colour = vec4(0.0);
}

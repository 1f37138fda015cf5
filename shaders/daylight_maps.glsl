// The daylight view's shadow maps (gl_daylight.cpp), as its passes read them: the room's and the
// image-based objects' (ibr_object.frag with DAYLIGHT). Per texel of a map the distance of the
// nearest room surface (red), of the nearest box or mesh face (green) and of the nearest
// image-based object's silhouette (blue) along the map's line. (The renderer prepends
// "#version 330 core" and MAX_MAPS.)
uniform sampler2D maps;        // per window sample's map (a tile of the atlas)
uniform ivec2 mapGrid;         // the atlas's columns and rows of tiles
uniform float mapTexels;       // a tile's side in texels
uniform sampler2D sunAtlas;    // the same per direction of the sun's disc
uniform ivec2 sunGrid;
uniform float sunTexels;
uniform int windowSamples;     // maps 0 .. windowSamples - 1; then the sun's four
uniform int sunMaps;           // 4 with a sun, else 0
// Per map seven vectors: its matrix (0-3), origin + a texel's width (per metre of distance, or
// metres), the window's normal or the light's direction + the sample's area, and the reach test
// (a cone's axis + cos of its half-angle, or a cylinder's radius). MAX_MAPS: the renderer's, as
// the context's largest uniform block holds (a uniform costs llvmpipe far less than a fetch).
layout(std140) uniform MapBlock {
  vec4 mapData[MAX_MAPS * 7];
};

// Map i's point ndc (both within (-1, 1)) in its atlas: tile i, row by row from the bottom, kept
// within the tile's outer texels' centres (rounding must not read the next map's border).
// (In floats: llvmpipe divides integers one lane at a time.)
vec2 atlasAt(int i, ivec2 grid, float texels, vec2 ndc) {
  vec2 g = vec2(grid);
  float row = floor((float(i) + 0.5) / g.x);
  vec2 inTile = clamp(0.5 * ndc + 0.5, vec2(0.5 / texels), vec2(1.0 - 0.5 / texels));
  return (vec2(float(i) - row * g.x, row) + inTile) / g;
}

// 0: the sample does not light p; 1: it lights p; 2: the room lets it through but an object
// blocks it (a box or mesh face, and with `images` an image-based object's silhouette too).
// `cosine`: p's surface against the line (the bias grows as it grazes).
int sampleState(int m, vec3 p, float cosine, float dist, bool images) {
  mat4 clip = mat4(mapData[m * 7 + 0], mapData[m * 7 + 1],
                   mapData[m * 7 + 2], mapData[m * 7 + 3]);
  vec4 c = clip * vec4(p, 1.0);
  float footprint = mapData[m * 7 + 4].w;
  if (m < windowSamples) footprint *= dist;  // perspective: a texel's width grows with distance
  float bias = 1.5 * footprint / max(cosine, 0.15) + 0.003;
  if (c.w <= 0.0) return 1;
  vec2 ndc = c.xy / c.w;
  if (abs(ndc.x) >= 1.0 || abs(ndc.y) >= 1.0) return 1;  // outside the map: no object there
  vec3 t = m < windowSamples ? texture(maps, atlasAt(m, mapGrid, mapTexels, ndc)).rgb
                             : texture(sunAtlas, atlasAt(m - windowSamples, sunGrid, sunTexels, ndc)).rgb;
  if (dist > t.r + bias) return 0;
  return (images ? min(t.g, t.b) : t.g) < dist - bias ? 2 : 1;
}

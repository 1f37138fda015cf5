#pragma once
// Match proposals for a clicked point (the TotalCalib workflow): where the point clicked in one
// photo probably is in another — along the epipolar line when both cameras are known, else
// anywhere — by normalised cross-correlation of the patch around the click.
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <vector>

#include "relume/geometry/camera.h"
#include "relume/reconstruct/colmap_model.h"
#include "relume/reconstruct/photos.h"
#include "relume/reconstruct/polygon_fit.h"

namespace relume::recon {

struct MatchProposal {
  glm::dvec2 pixel{0.0};
  double score = 0;  // NCC in [-1, 1]
};

// A photo prepared once for matching: its grey levels at full size and halved (2x2 means) until
// 800 pixels across or less. Proposals for many clicks reuse it instead of converting again.
struct MatchImage {
  int width = 0, height = 0;
  std::vector<std::vector<float>> levels;  // row-major grey levels (0-255), level k 2^k times smaller
  std::vector<int> widths, heights;
};
MatchImage prepareForMatching(const Image8& image);
// The same resampled to the camera's pinhole (its lens distortion removed), so that the sweep's
// pinhole cameras (ColmapModel::camera) fit the photo: clicks go in through pinholePixel and
// proposals come back through distortedPixel. A camera without distortion changes nothing.
MatchImage prepareForMatching(const Image8& image, const ColmapCamera& camera);
glm::dvec2 pinholePixel(const ColmapCamera& camera, glm::dvec2 distortedPixel);
glm::dvec2 distortedPixel(const ColmapCamera& camera, glm::dvec2 pinholePixel);

// Best `count` proposals in `b` for pixel `pa` of `a`, best first, at least `radius` pixels apart.
// With cameras (both non-null) only the epipolar line of `pa` is searched, the patch taken on
// planes through each depth: fronto-parallel, horizontal and vertical. `up` is the world's up
// (+z in a metric frame); unknown (zero), the up of photo a's image is taken for it. `planes`: the
// planes of polygons already built (in the cameras' frame): their orientations are
// tried as well, and the depths where the click's ray meets them.
std::vector<MatchProposal> proposeMatches(const Image8& a, glm::dvec2 pa, const Image8& b, const Camera* ca,
                                          const Camera* cb, int count = 3, int radius = 7,
                                          const glm::dvec3& up = glm::dvec3(0.0), const std::vector<Plane>& planes = {});
// The same on prepared photos. A large photo is swept on its coarsest level and the best peaks
// are refined at full size.
std::vector<MatchProposal> proposeMatches(const MatchImage& a, glm::dvec2 pa, const MatchImage& b, const Camera* ca,
                                          const Camera* cb, int count = 3, int radius = 7,
                                          const glm::dvec3& up = glm::dvec3(0.0), const std::vector<Plane>& planes = {});
// One click's proposals in several photos at once (in parallel), per photo as above; a photo
// where no proposal can be made (the click too near a border) gets none.
std::vector<std::vector<MatchProposal>> proposeMatchesInPhotos(const MatchImage& a, glm::dvec2 pa, const Camera& ca,
                                                               const std::vector<const MatchImage*>& photos,
                                                               const std::vector<const Camera*>& cameras, int count = 3,
                                                               int radius = 7, const glm::dvec3& up = glm::dvec3(0.0),
                                                               const std::vector<Plane>& planes = {});

}  // namespace relume::recon

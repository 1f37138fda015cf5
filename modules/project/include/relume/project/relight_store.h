#pragma once
// A preprocessed room in a Relume project: the scene (with the estimated albedos and lamp
// radiances in place of any it came with) plus relight/: relight.json (estimates, options,
// reference patches, texture grids) and per polygon its original, unoccluded and reflectance
// textures and the texel-source map as EXR files.
#include <functional>
#include <string>
#include <vector>

#include "relume/geometry/progress.h"
#include "relume/geometry/scene.h"
#include "relume/relight/relighter.h"

class QJsonArray;

namespace relume {

// Atomic like saveProject: a failure leaves any existing project as it was.
// `extra` may write further files (a front end's own state) into the staging folder.
void saveRelightProject(const Scene& scene, const RelightData& data, const std::string& folder,
                        Progress& progress = silentProgress(),
                        const std::function<void(const std::string&)>& extra = {});
// The relighting data of a project read with readProject; throws relume::Error naming the file
// when the project was not preprocessed or a file is missing or damaged.
RelightData readRelightData(const Scene& project);
// relight.json's bytes (`name` for the messages) for `project`: everything but the texture layers
// and glow images (readRelightData wraps it and loads those). What the fuzzing harness calls.
RelightData parseRelightJson(const std::string& bytes, const Scene& project, const std::string& name);
// The largest texture grid side relight.json may give (texels).
inline constexpr int kMaxTextureSide = 16384;
bool hasRelightData(const std::string& projectFolder);
// Painted reference regions as JSON ([{polygon, reference: [u, v], discs: [[u, v, r], ...]}]), as
// relight.json and the workbench's state keep them; the reader names `file` in its errors.
QJsonArray referenceRegionsJson(const std::vector<ReferenceRegion>& regions);
std::vector<ReferenceRegion> referenceRegionsFromJson(const QJsonArray& regions, const std::string& file);

}  // namespace relume

#pragma once
// Reading rooms (bundle folders, OBJ + JSON, Relume projects) and writing Relume projects.
#include <functional>
#include <string>
#include <vector>
#include <glm/vec3.hpp>

#include "relume/geometry/photometry.h"
#include "relume/geometry/progress.h"
#include "relume/geometry/scene.h"

namespace relume {

// What `path` names: a bundle folder (scene.json), a Relume project (a folder holding
// project.json, or that file itself), or an OBJ file with its JSON beside it (same stem).
// Every reader validates the scene (relume::validateScene) and the photos it lists.
Scene loadRoom(const std::string& path);

Scene readBundle(const std::string& folder);
Scene readObjWithJson(const std::string& objPath, const std::string& jsonPath);
Scene readProject(const std::string& projectPath);

// The bytes of a further file a JSON names (a bundle's geometry.obj, a virtual object's OBJ), by
// its name as the JSON gives it; throws relume::Error.
using FileBytes = std::function<std::string(const std::string& name)>;
// The readers above from bytes (`name`s for the messages): the scene, validated, its photos not
// checked and not confined (the readers wrap these and do both). What the fuzzing harnesses call.
// `files` gives the further files; empty, any is an error.
Scene parseProject(const std::string& bytes, const std::string& name, const FileBytes& files = {});
Scene parseBundle(const std::string& sceneJson, const std::string& name, const FileBytes& files);
Scene parseObjWithJson(const std::string& objBytes, const std::string& objName, const std::string& jsonBytes,
                       const std::string& jsonName, const FileBytes& files);

// Checks that every photo (and HDR) file exists and is a readable image of the camera's size.
void checkPhotos(const Scene& scene);

// Writes `scene` as a Relume project folder: project.json plus its photos copied into photos/.
// Atomic: the folder is assembled beside the target and renamed into place; an existing project
// is replaced only once the new one is complete. Throws relume::Error and leaves the old one.
// `extra` may write further files into the staging folder (its argument) before the swap.
void saveProject(const Scene& scene, const std::string& folder, Progress& progress = silentProgress(),
                 const std::function<void(const std::string&)>& extra = {});
// A lighting change as a JSON file: the fields of a variant in scene.json ("lights",
// "virtual_lights", "virtual_objects"); a virtual object may give "obj" (a mesh file, relative to
// the JSON file) instead of box_min / box_max.
Variant readVariantFile(const std::string& path);
// A luminaire's photometric file: IES LM-63 (.ies) or EULUMDAT (.ldt), told apart by its name's
// ending (or, for another ending, by a TILT= line); parseIes / parseEulumdat on its bytes.
PhotometricDistribution readPhotometricFile(const std::string& path);
Variant parseVariantFile(const std::string& bytes, const std::string& name, const FileBytes& files);

// The faces of an OBJ mesh (one polygon per `f` line, metres), for a virtual object.
std::vector<std::vector<glm::dvec3>> readObjFaces(const std::string& path);
// The same from an OBJ file's bytes (`name` for the messages).
std::vector<std::vector<glm::dvec3>> parseObjFaces(const std::string& bytes, const std::string& name);

// A file a project or bundle names: `rel` inside `folder`. Refused (relume::Error naming `file`
// and `element`) when `rel` is absolute, has a '..' component, or resolves (through symbolic
// links) outside the folder: a project someone sends cannot make Relume read or overwrite the
// user's other files. Returns the joined path. Every reader of a project or bundle checks the
// paths it lists with this; paths the user gives on the command line are not confined.
std::string fileInFolder(const std::string& folder, const std::string& rel, const std::string& file,
                         const std::string& element);

// 2: lamps may name photometric files (written only by projects that use them).
inline constexpr int kProjectVersion = 2;

}  // namespace relume

// Storing a document for a request and answering it, and dropping one (declared in routes.hpp), one template for
// scenes, meshes and images: the document goes to its store, and what was prepared to check it to the
// prepared cache, so the renders that follow find it ready. Every DocumentStore::PutResult maps to
// its answer here (201 or 200 with Location, 409, 413, 507, 422). What differs by kind is in the
// overloads below: a scene also names its static scene id (X-Scene-Id, the log line) and its
// expiry, and only a scene places other documents.
#include "server/problem.hpp"
#include "server/routes.hpp"

#include <httplib.h>

#include <stdexcept>

namespace rr::server {

namespace {

using nlohmann::json;

void note_storing(const StoredScene& scene) { request_context().scene_id = scene.static_id; }
void note_storing(const StoredMesh&) {}
void note_storing(const StoredTexture&) {}

// The store says only that something the scene uses is gone: the answer names the first mesh or
// image no longer stored (the first it uses, when every one is back by now).
[[noreturn]] void throw_missing_reference(ServiceState& state, const StoredScene& scene) {
  for (const std::string& id : scene.mesh_refs) {
    if (!state.stores.meshes->find(id, false)) {
      throw HttpError(422, "The stored mesh " + id + " that this scene places was deleted while it was stored.",
                      {{"", "there is no stored mesh \"" + id + "\""}});
    }
  }
  for (const std::string& id : scene.texture_refs) {
    if (!state.stores.textures->find(id, false)) {
      throw HttpError(422,
                      "The stored image " + id + " that this scene's textures name was deleted while it was stored.",
                      {{"", "there is no stored image \"" + id + "\""}});
    }
  }
  const std::string first = scene.mesh_refs.empty() ? scene.texture_refs.at(0) : scene.mesh_refs.at(0);
  throw HttpError(422, "The stored document " + first + " that this scene uses was deleted while it was stored.",
                  {{"", "there is no stored document \"" + first + "\""}});
}
[[noreturn]] void throw_missing_reference(ServiceState&, const StoredMesh&) {
  throw std::logic_error("a mesh places no stored document");
}
[[noreturn]] void throw_missing_reference(ServiceState&, const StoredTexture&) {
  throw std::logic_error("an image uses no stored document");
}

void add_answer_members(ServiceState& state, httplib::Response& res, const StoredScene& scene, json& body) {
  res.set_header("X-Scene-Id", scene.static_id);
  body["scene_id"] = scene.static_id;
  body["expires"] = time_or_null(state.stores.scenes->expiry_from_now());
}
void add_answer_members(ServiceState&, httplib::Response&, const StoredMesh&, json&) {}
void add_answer_members(ServiceState&, httplib::Response&, const StoredTexture&, json&) {}

StoredDocument document_of(const StoredScene& scene) { return scene_document(scene); }
StoredDocument document_of(const StoredMesh& mesh) { return mesh_document(mesh); }
StoredDocument document_of(const StoredTexture& texture) { return texture_document(texture); }

template <class T>
[[noreturn]] void throw_store_full(DocumentStore<T>& store) {
  const std::string kind = T::kind, plural = T::plural;
  CacheStats fill = store.stats();
  throw HttpError(507,
                  "The " + kind + " store is full: it holds " + std::to_string(fill.entries) + " " + plural +
                      " of at most " + std::to_string(fill.max_entries) + " and " + std::to_string(fill.bytes) +
                      " bytes of documents of at most " + std::to_string(fill.budget_bytes) + ". Stored " + plural +
                      " are kept, not evicted: delete " + plural +
                      " you no longer need, or ask the operator to raise --" + kind + "-store-entries or --" + kind +
                      "-store-bytes.",
                  {{"", kind + " store full"}});
}

}  // namespace

template <class T>
bool store_document(ServiceState& state, const std::shared_ptr<const T>& item) {
  const std::string kind = T::kind;
  note_storing(*item);
  DocumentStore<T>& store = state.stores.of<T>();
  using PutResult = typename DocumentStore<T>::PutResult;
  const StoredDocument document = document_of(*item);
  const PutResult result = store.put(document, request_context().owner);
  if (result == PutResult::created || result == PutResult::existed) state.cache.keep(item);
  switch (result) {
    case PutResult::conflict:
      throw HttpError(409,
                      "A different " + kind + " with the id " + item->id + " is stored already (a hash collision).",
                      {{"", "content differs from the stored " + kind + " with this id"}});
    case PutResult::too_large:
      throw HttpError(413,
                      "This " + kind + "'s document takes " + std::to_string(document.bytes()) + " bytes; the " + kind +
                          " store holds at most " + std::to_string(store.max_bytes()) + ".",
                      {{"", kind + " too large to store"}});
    case PutResult::full:
      throw_store_full(store);
    case PutResult::missing_reference:
      throw_missing_reference(state, *item);
    case PutResult::created:
      return true;
    case PutResult::existed:
      break;
  }
  return false;
}

template <class T>
void store_and_answer(ServiceState& state, httplib::Response& res, const std::shared_ptr<const T>& item, json body) {
  const bool created = store_document(state, item);
  const std::string location = location_of<T>(item->id);
  res.set_header("Location", location);
  body["id"] = item->id;
  body["location"] = location;
  body["created"] = created;
  add_answer_members(state, res, *item, body);
  send_json(res, body, created ? 201 : 200);
}

template <class T>
void release_and_answer(ServiceState& state, httplib::Response& res, const std::string& id,
                        const ReleaseWording& wording) {
  using ReleaseResult = typename DocumentStore<T>::ReleaseResult;
  const std::string the = std::string("The ") + wording.noun + " " + id;
  DocumentStore<T>& store = state.stores.of<T>();
  const ReleaseResult released = store.release(id, releasing_owner(state));
  if (released == ReleaseResult::removed) state.cache.forget<T>(id);
  switch (released) {
    case ReleaseResult::not_found:
      throw HttpError(404, std::string("There is no stored ") + wording.noun + " " + id + ".");
    case ReleaseResult::not_owner:
      throw HttpError(403, the + " is stored, but not by this token's owner; only an owner can drop its reference.");
    case ReleaseResult::read_only:
      if (wording.read_only_reason) throw HttpError(403, the + wording.read_only_reason);
      break;
    case ReleaseResult::pinned: {
      if (!wording.pinned_detail) break;
      std::vector<FieldError> errors;
      std::string list;
      for (const std::string& scene : store.pinned_by(id, 5)) {
        errors.push_back({"", std::string(wording.pinned_detail) + " " + scene});
        list += (list.empty() ? "" : ", ") + scene;
      }
      throw HttpError(409,
                      the + " is " + wording.pinned_summary + " (" + list + (errors.size() == 5 ? ", ..." : "") +
                          "); delete those scenes first. " + wording.pinned_rule,
                      errors);
    }
    case ReleaseResult::removed:
    case ReleaseResult::reference_dropped:
      break;
  }
  res.status = 204;
}

template bool store_document(ServiceState&, const std::shared_ptr<const StoredScene>&);
template bool store_document(ServiceState&, const std::shared_ptr<const StoredMesh>&);
template void store_and_answer(ServiceState&, httplib::Response&, const std::shared_ptr<const StoredScene>&, json);
template void store_and_answer(ServiceState&, httplib::Response&, const std::shared_ptr<const StoredMesh>&, json);
template bool store_document(ServiceState&, const std::shared_ptr<const StoredTexture>&);
template void store_and_answer(ServiceState&, httplib::Response&, const std::shared_ptr<const StoredTexture>&, json);
template void release_and_answer<StoredScene>(ServiceState&, httplib::Response&, const std::string&,
                                              const ReleaseWording&);
template void release_and_answer<StoredMesh>(ServiceState&, httplib::Response&, const std::string&,
                                             const ReleaseWording&);
template void release_and_answer<StoredTexture>(ServiceState&, httplib::Response&, const std::string&,
                                                const ReleaseWording&);

}  // namespace rr::server

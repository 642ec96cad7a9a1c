#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <simreel/error.hpp>
#include "app/scene/mesh_import.hpp"
#include "app/scene/text.hpp"

#if defined(__SANITIZE_ADDRESS__)
#define SIMREEL_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SIMREEL_ASAN 1
#endif
#endif

namespace simreel {
namespace detail {

// Everything else assimp reads. Only validation is asked of assimp's post-processing: its
// Triangulate and SortByPType steps crash on some broken files (an assertion; a stack write, assimp
// PR #5138), and simreel does both itself: node transforms baked in here (in double precision),
// polygons ear-clipped by add_polygon, points and lines counted.
RawMesh assimp_read(const std::string& path) {
  Assimp::Importer imp;
  const aiScene* sc = imp.ReadFile(path, aiProcess_ValidateDataStructure);
  if (!sc || !sc->mRootNode)
    throw InputError("cannot read mesh '" + path + "': " + std::string(imp.GetErrorString()));
  RawMesh out;
  bool all_normals = true, all_uvs = true, all_colors = true;
  std::vector<int> poly;
  // Nodes depth first with their world transforms; a node graph is a tree, but never trusted to be.
  std::vector<std::pair<const aiNode*, Eigen::Matrix4d>> stack{{sc->mRootNode, Eigen::Matrix4d::Identity()}};
  long visited = 0;
  while (!stack.empty()) {
    const auto [node, parent] = stack.back();
    stack.pop_back();
    if (++visited > 10000000) throw InputError("mesh '" + path + "': its node graph does not end");
    Eigen::Matrix4d local;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) local(r, c) = node->mTransformation[r][c];
    const Eigen::Matrix4d T = parent * local;
    const Eigen::Matrix3d L = T.topLeftCorner<3, 3>();
    const Eigen::Matrix3d N = L.determinant() != 0 ? Eigen::Matrix3d(L.inverse().transpose()) : L;
    for (unsigned k = 0; k < node->mNumMeshes; ++k) {
      if (node->mMeshes[k] >= sc->mNumMeshes) throw InputError("mesh '" + path + "': a node names no mesh");
      const aiMesh* m = sc->mMeshes[node->mMeshes[k]];
      const int base = (int)out.vertices.size();
      all_normals = all_normals && m->HasNormals();
      all_uvs = all_uvs && m->HasTextureCoords(0);
      all_colors = all_colors && m->HasVertexColors(0);
      for (unsigned v = 0; v < m->mNumVertices; ++v) {
        if (m->HasTextureCoords(0))
          out.uvs.emplace_back(m->mTextureCoords[0][v].x, m->mTextureCoords[0][v].y);
        // glTF's COLOR_0 is linear already (and assimp passes other formats' colours as written).
        if (m->HasVertexColors(0))
          out.colors.push_back({std::clamp(m->mColors[0][v].r, 0.f, 1.f),
                                std::clamp(m->mColors[0][v].g, 0.f, 1.f),
                                std::clamp(m->mColors[0][v].b, 0.f, 1.f)});
        const aiVector3D& p = m->mVertices[v];
        out.vertices.push_back((T * Eigen::Vector4d(p.x, p.y, p.z, 1)).head<3>());
        out.normals.push_back(
            m->HasNormals()
                ? Eigen::Vector3f(
                      (N * Vec3(m->mNormals[v].x, m->mNormals[v].y, m->mNormals[v].z)).cast<float>())
                : Eigen::Vector3f::Zero());
      }
      for (unsigned f = 0; f < m->mNumFaces; ++f) {
        const aiFace& face = m->mFaces[f];
        poly.clear();
        for (unsigned i = 0; i < face.mNumIndices; ++i) {
          if (face.mIndices[i] >= m->mNumVertices)
            throw InputError("mesh '" + path + "': face refers to a vertex that does not exist");
          poly.push_back(base + (int)face.mIndices[i]);
        }
        add_polygon(out, poly, {}, (int)m->mMaterialIndex);
      }
    }
    for (unsigned c = 0; c < node->mNumChildren; ++c) stack.emplace_back(node->mChildren[c], T);
  }
  if (!all_normals) out.normals.clear();
  if (!all_uvs) out.uvs.clear();
  if (!all_colors) out.colors.clear();
  for (unsigned i = 0; i < sc->mNumMaterials; ++i) {
    aiColor4D c;
    const aiMaterial* mat = sc->mMaterials[i];
    if (mat->Get(AI_MATKEY_BASE_COLOR, c) == AI_SUCCESS || mat->Get(AI_MATKEY_COLOR_DIFFUSE, c) == AI_SUCCESS)
      out.materials.push_back(
          {std::clamp(c.r, 0.f, 1.f), std::clamp(c.g, 0.f, 1.f), std::clamp(c.b, 0.f, 1.f)});
    else
      out.materials.push_back({-1.f, -1.f, -1.f});
    aiString name;
    out.material_names.push_back(mat->Get(AI_MATKEY_NAME, name) == AI_SUCCESS ? name.C_Str() : "");
    // The base-colour image: glTF's baseColorTexture, else the classic diffuse map.
    aiString tex;
    if (mat->GetTexture(aiTextureType_BASE_COLOR, 0, &tex) != AI_SUCCESS &&
        mat->GetTexture(aiTextureType_DIFFUSE, 0, &tex) != AI_SUCCESS)
      tex.Clear();
    std::string ref = tex.C_Str();
    // An image inside the file (a glb's "*0", or one named by file name): sent back as its bytes,
    // named "*N" by its place in `embedded`.
    if (!ref.empty()) {
      if (const aiTexture* t = sc->GetEmbeddedTexture(tex.C_Str())) {
        std::string bytes;
        if (t->mHeight == 0) {  // compressed (PNG, JPEG...): mWidth bytes
          bytes.assign(reinterpret_cast<const char*>(t->pcData), t->mWidth);
        } else {  // raw BGRA texels: sent as the renderer's raw RGBA format (render/image.hpp)
          bytes = raw_rgba_header(t->mWidth, t->mHeight);
          for (size_t k = 0; k < (size_t)t->mWidth * t->mHeight; ++k) {
            const aiTexel& x = t->pcData[k];
            bytes += {(char)x.r, (char)x.g, (char)x.b, (char)x.a};
          }
        }
        ref = "*" + std::to_string(out.embedded.size());
        out.embedded.push_back(std::move(bytes));
      }
    }
    out.material_textures.push_back(ref);
  }
  return out;
}

// ---- the child's reply: "SRM1" + counts + arrays, or "SRE1" + an error message ---------------

namespace {

template <typename T>
void put(std::string& s, const T& v) {
  s.append(reinterpret_cast<const char*>(&v), sizeof v);
}
template <typename T>
void put_all(std::string& s, const std::vector<T>& v) {
  put(s, (uint64_t)v.size());
  if (!v.empty()) s.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

class Cursor {
 public:
  Cursor(std::string_view b, const std::string& path, const char* who) : b_(b), path_(path), who_(who) {}
  [[noreturn]] void bad() const {
    throw InputError(std::string(who_) + " could not read '" + path_ +
                     "' (its reader process sent a broken reply)");
  }
  template <typename T>
  T get() {
    if (b_.size() < sizeof(T)) bad();
    T v;
    std::memcpy(&v, b_.data(), sizeof v);
    b_.remove_prefix(sizeof v);
    return v;
  }
  // A count is trusted only as far as the bytes left can hold it.
  template <typename T>
  void get_all(std::vector<T>& v) {
    const uint64_t n = get<uint64_t>();
    if (n > b_.size() / sizeof(T)) bad();
    v.resize(n);
    if (n) std::memcpy(static_cast<void*>(v.data()), b_.data(), n * sizeof(T));
    b_.remove_prefix(n * sizeof(T));
  }
  std::string text() {
    std::vector<char> c;
    get_all(c);
    return std::string(c.begin(), c.end());
  }
  void texts(std::vector<std::string>& out) {
    const uint64_t n = get<uint64_t>();
    if (n > b_.size() / 8) bad();  // each at least 8 bytes: bounded
    out.clear();
    for (uint64_t i = 0; i < n; ++i) out.push_back(text());
  }
  bool done() const { return b_.empty(); }

 private:
  std::string_view b_;
  const std::string& path_;
  const char* who_;
};

void put_texts(std::string& s, const std::vector<std::string>& v) {
  put(s, (uint64_t)v.size());
  for (const std::string& t : v) put_all(s, std::vector<char>(t.begin(), t.end()));
}

std::string encode_error(const std::string& msg) {
  std::string s = "SRE1";
  put_all(s, std::vector<char>(msg.begin(), msg.end()));
  return s;
}

bool write_all(int fd, const char* p, size_t n) {
  while (n > 0) {
    const ssize_t w = ::write(fd, p, n);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) return false;
    p += w;
    n -= (size_t)w;
  }
  return true;
}

std::string signal_name(int sig) {
  const char* a = sigabbrev_np(sig);
  return a ? "SIG" + std::string(a) : "signal " + std::to_string(sig);
}

constexpr size_t kMaxReply = size_t(1) << 32;  // 4 GiB: about 100 million triangles

}  // namespace

std::string encode_mesh(const RawMesh& m) {
  std::string s = "SRM1";
  put_all(s, m.vertices);
  put_all(s, m.normals);
  put_all(s, m.triangles);
  put_all(s, m.triangle_normals);
  put_all(s, m.triangle_material);
  put_all(s, m.materials);
  put_texts(s, m.material_names);
  put_texts(s, m.material_textures);
  put_texts(s, m.embedded);
  put_all(s, m.uvs);
  put_all(s, m.triangle_uvs);
  put_all(s, m.colors);
  put(s, (int64_t)m.points_and_lines);
  put_texts(s, m.notes);
  return s;
}

RawMesh decode_mesh(std::string_view bytes, const std::string& path, const char* who) {
  Cursor c(bytes, path, who);
  const uint32_t magic = c.get<uint32_t>();
  uint32_t mesh_magic, error_magic;
  std::memcpy(&mesh_magic, "SRM1", 4);
  std::memcpy(&error_magic, "SRE1", 4);
  if (magic == error_magic) {
    const std::string msg = c.text();
    if (!c.done()) c.bad();
    throw InputError(msg);
  }
  if (magic != mesh_magic) c.bad();
  RawMesh m;
  c.get_all(m.vertices);
  c.get_all(m.normals);
  c.get_all(m.triangles);
  c.get_all(m.triangle_normals);
  c.get_all(m.triangle_material);
  c.get_all(m.materials);
  c.texts(m.material_names);
  c.texts(m.material_textures);
  c.texts(m.embedded);
  c.get_all(m.uvs);
  c.get_all(m.triangle_uvs);
  c.get_all(m.colors);
  m.points_and_lines = c.get<int64_t>();
  c.texts(m.notes);
  if (!c.done() || m.points_and_lines < 0) c.bad();
  // What import_mesh indexes with must be in range.
  const auto in = [](int i, size_t n) { return i >= 0 && (size_t)i < n; };
  for (const auto& t : m.triangles)
    for (int i : t)
      if (!in(i, m.vertices.size())) c.bad();
  if (!m.triangle_normals.empty() && m.triangle_normals.size() != m.triangles.size()) c.bad();
  for (const auto& t : m.triangle_normals)
    for (int i : t)
      if (!in(i, m.normals.size())) c.bad();
  if (!m.triangle_uvs.empty() && m.triangle_uvs.size() != m.triangles.size()) c.bad();
  for (const auto& t : m.triangle_uvs)
    for (int i : t)
      if (!in(i, m.uvs.size())) c.bad();
  for (auto* v : {&m.material_names, &m.material_textures}) {
    if (!v->empty() && v->size() != m.materials.size()) c.bad();
    v->resize(m.materials.size());
  }
  return m;
}

RawMesh contained_read(const std::string& path, const char* who, const std::function<RawMesh()>& read,
                       double seconds) {
  const std::string fail = std::string(who) + " could not read '" + path + "'";
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0) throw std::runtime_error("pipe: " + std::string(std::strerror(errno)));
  const pid_t pid = fork();
  if (pid < 0) {
    close(fds[0]);
    close(fds[1]);
    throw std::runtime_error("fork: " + std::string(std::strerror(errno)));
  }
  if (pid == 0) {  // the child: read, reply, _exit (no atexit handlers, no stdio flush of the parent's)
    close(fds[0]);
    signal(SIGPIPE, SIG_DFL);
    // A crash in here must end the child by its signal, so the parent can name it, even where a
    // sanitizer (ASan turns SIGSEGV and SIGBUS into exit status 1) or the parent's stop handlers
    // installed their own.
    for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGINT, SIGTERM, SIGHUP, SIGQUIT})
      signal(sig, SIG_DFL);
#ifndef SIMREEL_ASAN
    // Memory: half the machine at most, so a file that claims billions of records fails in here.
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
    if (pages > 0 && page > 0) {
      const rlim_t half = (rlim_t)pages * (rlim_t)page / 2;
      const rlimit lim{half, half};
      setrlimit(RLIMIT_AS, &lim);
    }
#endif
    std::string reply;
    try {
      reply = encode_mesh(read());
    } catch (const InputError& e) {
      reply = encode_error(e.what());
    } catch (const std::bad_alloc&) {
      reply = encode_error(fail + " (ran out of memory)");
    } catch (const std::exception& e) {
      reply = encode_error(fail + " (" + e.what() + ")");
    } catch (...) {
      reply = encode_error(fail + " (an unknown exception)");
    }
    _exit(write_all(fds[1], reply.data(), reply.size()) ? 0 : 3);
  }
  close(fds[1]);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  std::string reply;
  std::string why;  // set when the parent gives up
  char buf[65536];
  for (;;) {
    const double left = std::chrono::duration<double>(deadline - std::chrono::steady_clock::now()).count();
    if (left <= 0) {
      char b[64];
      std::snprintf(b, sizeof b, "gave up after %g s", seconds);
      why = b;
      break;
    }
    pollfd p{fds[0], POLLIN, 0};
    const int r = poll(&p, 1, (int)std::min(left * 1000 + 1, 1e9));
    if (r < 0 && errno == EINTR) continue;
    if (r < 0) {
      why = "poll: " + std::string(std::strerror(errno));
      break;
    }
    if (r == 0) continue;
    const ssize_t n = ::read(fds[0], buf, sizeof buf);
    if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
    if (n <= 0) break;  // end of the reply
    if (reply.size() + (size_t)n > kMaxReply) {
      why = "its reply exceeds " + std::to_string(kMaxReply >> 20) + " MiB";
      break;
    }
    reply.append(buf, (size_t)n);
  }
  close(fds[0]);
  if (!why.empty()) kill(pid, SIGKILL);
  // The pipe is closed: the child is exiting. Wait for it (2 s at most, on a pidfd where the kernel
  // has them), then kill it if it lingers.
  int status = 0;
  const int pidfd = (int)syscall(SYS_pidfd_open, pid, 0);
  if (pidfd >= 0) {
    pollfd p{pidfd, POLLIN, 0};
    while (poll(&p, 1, 2000) < 0 && errno == EINTR) {
    }
    close(pidfd);
  }
  for (int tries = 0;; ++tries) {
    const pid_t w = waitpid(pid, &status, tries < 2000 ? WNOHANG : 0);
    if (w == pid) break;
    if (w < 0 && errno != EINTR) break;
    if (tries == 2000 - 1) kill(pid, SIGKILL);
    if (w == 0) usleep(1000);
  }
  if (!why.empty()) throw InputError(fail + " (" + why + ")");
  if (WIFSIGNALED(status)) throw InputError(fail + " (crashed: " + signal_name(WTERMSIG(status)) + ")");
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw InputError(fail + " (its reader process exited with status " +
                     std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + ")");
  return decode_mesh(reply, path, who);
}

}  // namespace detail

namespace {

// Where a material's image is: beside the mesh as written (relative), as written (absolute), else,
// for a path from another machine (Windows drive letters and backslashes, an absolute path that is
// not here), the file of that name beside the mesh, with a note. "" when none is found.
std::string resolve_texture(const std::string& ref, const std::filesystem::path& dir,
                            const std::string& material, std::vector<std::string>& notes) {
  namespace fs = std::filesystem;
  std::string unix_ref = ref;
  std::replace(unix_ref.begin(), unix_ref.end(), '\\', '/');
  const bool foreign = unix_ref != ref || (ref.size() > 1 && ref[1] == ':');
  auto usable = [](const fs::path& p) {
    std::error_code ec;
    return fs::is_regular_file(p, ec);
  };
  const fs::path as_written = fs::path(unix_ref).is_absolute() ? fs::path(unix_ref) : dir / unix_ref;
  if (!foreign && usable(as_written)) return as_written.string();
  const fs::path beside = dir / fs::path(unix_ref).filename();
  const std::string who = material.empty() ? "a material" : "material '" + material + "'";
  if (usable(beside)) {
    notes.push_back("texture '" + ref + "' of " + who + " is not here; using '" +
                    fs::path(unix_ref).filename().string() + "' beside the mesh");
    return beside.string();
  }
  notes.push_back("texture '" + ref + "' of " + who + " not found (looked beside the mesh, in '" +
                  (dir.empty() ? std::string(".") : dir.string()) + "'): drawn in the material's colour");
  return "";
}

// The file's look beyond one colour (render/material.hpp): null when it has none (every face one
// colour, no image, no vertex colours), so a plain mesh is drawn as before, in one colour.
std::shared_ptr<const MeshAppearance> appearance_of(const detail::RawMesh& r, const std::string& path,
                                                    std::vector<std::string>& notes) {
  namespace fs = std::filesystem;
  const size_t nt = r.triangles.size();
  auto a = std::make_shared<MeshAppearance>();
  const bool per_face = r.triangle_material.size() == nt && !r.materials.empty();
  std::vector<char> used(r.materials.size(), 0);
  if (per_face)
    for (int mat : r.triangle_material)
      if (mat >= 0 && mat < (int)used.size()) used[mat] = 1;
  const bool have_uvs = !r.uvs.empty() && (r.triangle_uvs.size() == nt || r.uvs.size() == r.vertices.size());
  std::map<std::string, int> texture_of;  // resolved file or "*N": its index in a->textures
  const fs::path dir = fs::path(path).parent_path();
  bool textured = false, no_uv_note = false;
  for (size_t i = 0; i < r.materials.size(); ++i) {
    SurfaceMaterial sm;
    sm.name = i < r.material_names.size() ? r.material_names[i] : "";
    sm.color = r.materials[i];
    const std::string ref = i < r.material_textures.size() ? r.material_textures[i] : "";
    if (used[i] && !ref.empty()) {
      std::string ext = fs::path(ref).extension().string();
      for (char& ch : ext) ch = (char)std::tolower((unsigned char)ch);
      const std::string who = sm.name.empty() ? "a material" : "material '" + sm.name + "'";
      std::string key;
      TextureSource src;
      src.name = ref;
      if (ext == ".ktx2" || ext == ".ktx" || ext == ".basis" || ext == ".dds") {
        notes.push_back("texture '" + ref + "' of " + who + " is " + ext.substr(1) +
                        ", a GPU format simreel does not decode: drawn in the material's colour");
      } else if (!have_uvs) {
        if (!no_uv_note)
          notes.push_back(who + " has a texture ('" + ref +
                          "') but the mesh has no texture coordinates: drawn in the material's colour");
        no_uv_note = true;
      } else if (ref[0] == '*') {
        const long k = std::strtol(ref.c_str() + 1, nullptr, 10);
        if (k >= 0 && k < (long)r.embedded.size()) {
          key = ref;
          src.bytes = std::make_shared<const std::string>(r.embedded[k]);
        }
      } else {
        src.file = resolve_texture(ref, dir, sm.name, notes);
        key = src.file;
      }
      if (!key.empty()) {
        auto [it, fresh] = texture_of.emplace(key, (int)a->textures.size());
        if (fresh) a->textures.push_back(std::move(src));
        sm.texture = it->second;
        textured = true;
      }
    }
    a->materials.push_back(std::move(sm));
  }
  // More than one colour among the materials faces use?
  bool several = false;
  const std::array<float, 3>* first = nullptr;
  for (size_t i = 0; i < used.size(); ++i)
    if (used[i]) {
      if (first && *first != r.materials[i]) several = true;
      first = &r.materials[i];
    }
  if (per_face)
    for (int mat : r.triangle_material) several = several || mat < 0 || mat >= (int)r.materials.size();
  const bool colours = !r.colors.empty() && r.colors.size() == r.vertices.size();
  a->varies = (several && per_face) || textured || colours;
  if (!a->varies && !have_uvs) return nullptr;
  a->triangle_material.assign(nt, -1);
  if (per_face)
    for (size_t f = 0; f < nt; ++f) {
      const int mat = r.triangle_material[f];
      a->triangle_material[f] = mat >= 0 && mat < (int)r.materials.size() ? mat : -1;
    }
  if (have_uvs) {
    a->corner_uv.resize(nt);
    for (size_t f = 0; f < nt; ++f)
      for (int k = 0; k < 3; ++k)
        a->corner_uv[f][k] = r.uvs[r.triangle_uvs.size() == nt ? r.triangle_uvs[f][k] : r.triangles[f][k]];
  }
  if (colours) {
    a->corner_color.resize(nt);
    for (size_t f = 0; f < nt; ++f)
      for (int k = 0; k < 3; ++k) a->corner_color[f][k] = r.colors[r.triangles[f][k]];
  }
  return a;
}

}  // namespace

ImportedMesh import_mesh(const std::string& path, const Vec3& scale) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec && ec != std::errc::no_such_file_or_directory)
    throw InputError("mesh file '" + path + "': " + ec.message());
  if (!fs::exists(st)) throw InputError("mesh file '" + path + "' does not exist");
  if (fs::is_directory(st)) throw InputError("mesh file '" + path + "' is a directory, not a file");
  if (!fs::is_regular_file(st))
    throw InputError("mesh file '" + path + "' is not a regular file (a FIFO, socket or device)");
  ImportedMesh out;
  // The extension picks simreel's reader; a file whose bytes announce PLY, OFF or STL goes to that
  // reader whatever its name, so assimp never sees a file simreel's readers would refuse.
  std::string ext = lower_extension(path);
  std::optional<detail::RawMesh> raw;
  const bool native = ext == ".obj" || ext == ".off" || ext == ".stl" || ext == ".ply";
  std::string text;
  if (native) {
    text = detail::read_file(path);
  } else {  // the first bytes and the size tell
    std::ifstream f(path, std::ios::binary);
    char head[512];
    f.read(head, sizeof head);
    const std::string sniffed =
        detail::native_format(std::string_view(head, (size_t)f.gcount()), fs::file_size(path, ec));
    if (!sniffed.empty()) {
      ext = "." + sniffed;
      text = detail::read_file(path);
    }
  }
  if (ext == ".obj") {
    raw = detail::parse_obj(text, path);
    out.reader = "obj";
  } else if (ext == ".off") {
    raw = detail::parse_off(text, path);
    out.reader = "off";
  } else if (ext == ".stl") {
    raw = detail::parse_stl(text, path, &out.reader);
  } else if (ext == ".ply") {
    raw = detail::parse_ply(text, path, &out.reader);
  } else {
    raw = detail::contained_read(path, "assimp", [&] { return detail::assimp_read(path); });
    out.reader = "assimp";
  }
  detail::RawMesh& r = *raw;
  out.notes.insert(out.notes.end(), r.notes.begin(), r.notes.end());
  if (r.points_and_lines)
    out.notes.push_back("skipped " + std::to_string(r.points_and_lines) +
                        " points or lines (only triangles have volume)");
  if (r.triangles.empty())
    throw InputError("mesh '" + path + "' has no triangles" +
                     (r.points_and_lines
                          ? " (only " + std::to_string(r.points_and_lines) + " points or lines)"
                          : std::string()));
  // Only the vertices faces use, in first-use order (a hull must not see stray points).
  std::vector<int> remap(r.vertices.size(), -1);
  TriangleMesh& m = out.mesh;
  for (const auto& t : r.triangles) {
    std::array<int, 3> u;
    for (int k = 0; k < 3; ++k) {
      int& id = remap[t[k]];
      if (id < 0) {
        id = (int)m.vertices.size();
        const Vec3& p = r.vertices[t[k]];
        if (!all_finite(p))
          throw InputError("mesh '" + path + "' has a vertex with a NaN or infinite coordinate");
        m.vertices.push_back(p.cwiseProduct(scale));
        if (!all_finite(m.vertices.back())) {
          std::ostringstream os;
          os << "mesh '" << path << "': vertex (" << p.x() << ", " << p.y() << ", " << p.z()
             << ") overflows double precision when scaled by (" << scale.x() << ", " << scale.y() << ", "
             << scale.z() << ")";
          throw InputError(os.str());
        }
      }
      u[k] = id;
    }
    m.triangles.push_back(u);
  }
  // Shading normals: per corner (OBJ) or per vertex (PLY, assimp). A scale s maps normals by s^-1.
  const bool per_corner = !r.triangle_normals.empty();
  const bool per_vertex = !per_corner && !r.normals.empty() && r.normals.size() == r.vertices.size();
  if (per_corner || per_vertex) {
    const Eigen::Vector3f inv = scale.cwiseInverse().cast<float>();
    for (size_t f = 0; f < r.triangles.size(); ++f) {
      std::array<Eigen::Vector3f, 3> c;
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3f n =
            r.normals[per_corner ? r.triangle_normals[f][k] : r.triangles[f][k]].cwiseProduct(inv);
        c[k] = n.norm() > 0 && n.allFinite() ? Eigen::Vector3f(n.normalized()) : Eigen::Vector3f::Zero();
      }
      out.corner_normals.push_back(c);
    }
  }
  // The colour of the material most faces use, if the file gives it one.
  if (!r.materials.empty() && r.triangle_material.size() == r.triangles.size()) {
    std::vector<long> uses(r.materials.size(), 0);
    for (int mat : r.triangle_material)
      if (mat >= 0 && mat < (int)uses.size()) ++uses[mat];
    const size_t best = std::max_element(uses.begin(), uses.end()) - uses.begin();
    if (uses[best] > 0 && r.materials[best][0] >= 0) out.color = r.materials[best];
  }
  out.appearance = appearance_of(r, path, out.notes);
  return out;
}

}  // namespace simreel

#include "bake/io/mesh_files.h"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>
#include <sstream>
#include <streambuf>
#include <string>
#include <vector>

#include "bake/input_file.h"
#include "bake/io/input_limits.h"
#include "bake/io/scene_load.h"
#include "bake/io/shapes.h"

namespace lb {

namespace {

using OpenMeshTriangles = OpenMesh::TriMesh_ArrayKernelT<>;

size_t count_occurrences(const std::string& text, const std::string& word) {
  size_t count = 0;
  for (size_t at = text.find(word); at != std::string::npos; at = text.find(word, at + 1)) ++count;
  return count;
}

// std::getline that reads at most `cap` + 1 bytes of one line (a longer line comes back
// `cap` + 1 long, for the caller to refuse) through `buffer` (cap + 2 bytes, made once); false
// at the end of the stream.
bool read_bounded_line(std::istream& in, std::vector<char>& buffer, std::string& line,
                       size_t cap) {
  buffer.resize(cap + 2);
  in.getline(buffer.data(), std::streamsize(buffer.size()));
  const auto read = size_t(in.gcount());
  if (in.fail() && !in.eof() && read == cap + 1) {  // no newline within cap + 1 bytes
    line.assign(buffer.data(), cap + 1);
    return true;
  }
  line.assign(buffer.data(), read > 0 && !in.eof() ? read - 1 : read);  // gcount counts '\n'
  if (in.eof()) return read > 0;
  return !in.fail();
}

// OpenMesh silently skips faces with bad indices, reads "nan" as whatever the stream gives and
// turns 1e39 into infinity; a quick pass over an OBJ finds these with their line numbers.
// Returns how many faces repeat a vertex (the reader drops those).
size_t check_obj_text(const std::string& path, const std::string& where) {
  std::ifstream in(path);
  std::string line;
  size_t line_number = 0, vertices = 0, texcoords = 0, normals = 0, repeated = 0;
  auto fail = [&](const std::string& message) {
    throw SceneError(where + ": " + path + ":" + std::to_string(line_number) + ": " + message);
  };
  // OpenMesh skips a v, vt or vn line with fewer numbers than `count` (and then indexes past
  // its arrays for the faces that use it), so each must have them in full.
  auto check_numbers = [&](std::istringstream& fields, int count, const char* what) {
    std::string token;
    for (int axis = 0; axis < count; ++axis) {
      if (!(fields >> token))
        fail(std::string(what) + "s: found " + std::to_string(axis) + ", need " +
             std::to_string(count));
      char* end = nullptr;
      const double value = std::strtod(token.c_str(), &end);
      if (end != token.c_str() + token.size())
        fail(std::string(what) + " '" + token + "' is not a number");
      if (!std::isfinite(value)) fail(std::string(what) + " '" + token + "' is not finite");
      if (std::abs(value) > limits::kMaxCoordinate)
        fail(std::string(what) + " '" + token + "' is out of range (|x| above 1e18)");
    }
  };
  // One reference of a face corner "v/vt/vn": 1-based, negative counts back from the last.
  auto check_reference = [&](const std::string& text, size_t defined, const char* what,
                             const char* defined_kind) -> long {
    char* end = nullptr;
    const long index = std::strtol(text.c_str(), &end, 10);
    if (end == text.c_str()) fail(std::string(what) + " '" + text + "' is not a number");
    const long resolved = index < 0 ? long(defined) + index + 1 : index;
    if (index == 0 || resolved < 1 || resolved > long(defined))
      fail(std::string(what) + " " + std::to_string(index) + " out of range (" +
           std::to_string(defined) + " " + defined_kind + " so far)");
    return resolved;
  };
  std::vector<char> buffer;
  while (read_bounded_line(in, buffer, line, limits::kMaxTextLineBytes)) {
    ++line_number;
    if (line.size() > limits::kMaxTextLineBytes)
      fail("line longer than " + std::to_string(limits::kMaxTextLineBytes >> 20) +
           " MiB (bake/io/input_limits.h): not a text OBJ file");
    std::istringstream fields(line);
    std::string tag;
    fields >> tag;
    if (tag == "v") {
      ++vertices;
      check_numbers(fields, 3, "vertex coordinate");
    } else if (tag == "vt") {
      ++texcoords;
      check_numbers(fields, 2, "texture coordinate");
    } else if (tag == "vn") {
      ++normals;
      check_numbers(fields, 3, "normal");
    } else if (tag == "f") {
      std::string corner;
      std::vector<long> face;
      while (fields >> corner) {
        if (face.size() == limits::kMaxPolygonVertices)
          fail("face has more than " + std::to_string(limits::kMaxPolygonVertices) +
               " vertices (bake/io/input_limits.h); split it");
        const size_t slash = corner.find('/');
        face.push_back(
            check_reference(corner.substr(0, slash), vertices, "face index", "vertices"));
        if (slash == std::string::npos) continue;
        const size_t second = corner.find('/', slash + 1);
        const std::string uv = corner.substr(slash + 1, second - slash - 1);
        if (!uv.empty()) check_reference(uv, texcoords, "face texture coordinate index", "vt");
        if (second != std::string::npos && second + 1 < corner.size())
          check_reference(corner.substr(second + 1), normals, "face normal index", "vn");
      }
      std::sort(face.begin(), face.end());
      if (std::adjacent_find(face.begin(), face.end()) != face.end()) ++repeated;
    }
  }
  return repeated;
}

// A binary STL's size is fixed by its triangle count; OpenMesh would read past a short file.
void check_binary_stl_size(const std::string& path, const std::string& where) {
  std::ifstream in(path, std::ios::binary);
  char head[5] = {};
  in.read(head, 5);
  const uintmax_t size = std::filesystem::file_size(path);
  if (std::string(head, 5) == "solid") {
    // ASCII unless the "solid" is just a binary header's first bytes.
    std::stringstream text;
    text << in.rdbuf();
    if (text.str().find("facet") != std::string::npos) return;
  }
  if (size < 84)
    throw SceneError(where + ": truncated binary STL '" + path + "': " + std::to_string(size) +
                     " bytes, the header alone needs 84");
  in.clear();
  in.seekg(80);
  uint32_t triangles = 0;
  in.read(reinterpret_cast<char*>(&triangles), 4);
  const uintmax_t expected = 84 + 50 * uintmax_t(triangles);
  if (size < expected)
    throw SceneError(where + ": truncated binary STL '" + path + "': header says " +
                     std::to_string(triangles) + " triangles (" + std::to_string(expected) +
                     " bytes), file has " + std::to_string(size));
}

size_t ply_type_size(const std::string& type) {
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
  if (type == "int" || type == "uint" || type == "float" || type == "int32" || type == "uint32" ||
      type == "float32")
    return 4;
  if (type == "double" || type == "float64") return 8;
  return 0;
}

// A PLY header's element counts must be non-negative and fit the file (every element takes at
// least a byte); a binary PLY's header also fixes a lower bound on its size (faces have at least
// 3 indices), so a shorter file is truncated, whatever a reader would make of the missing bytes.
void check_ply_header(const std::string& path, const std::string& where) {
  std::ifstream in(path, std::ios::binary);
  const uintmax_t size = std::filesystem::file_size(path);
  std::string line;
  bool binary = false;
  uintmax_t minimum = 0, element_count = 0;
  size_t line_number = 0, elements = 0;
  auto fail = [&](const std::string& message) {
    throw SceneError(where + ": " + path + ":" + std::to_string(line_number) + ": " + message);
  };
  auto add = [&](uintmax_t bytes_per_element) {  // element_count <= size, so no overflow
    minimum = std::min<uintmax_t>(minimum + element_count * bytes_per_element, UINTMAX_MAX / 2);
  };
  while (std::getline(in, line)) {
    ++line_number;
    // Words as OpenMesh's header parser reads them: split at any white space, so
    // "1.0\velement" is two words on one line.
    std::istringstream stream(line);
    std::vector<std::string> words;
    for (std::string word; stream >> word;) words.push_back(word);
    const std::string keyword = words.empty() ? std::string() : words[0];
    // That parser also trusts the structure (a property before any element crashed it): only
    // the PLY 1.0 keywords are let through, in their order, each with exactly its words.
    auto expect_words = [&](size_t count) {
      if (words.size() != count)
        fail("'" + keyword + "' line with " + std::to_string(words.size()) + " words, expected " +
             std::to_string(count));
    };
    if (line_number == 1) {
      if (keyword != "ply") fail("not a PLY file (the first line is not 'ply')");
      expect_words(1);
    } else if (keyword == "format") {
      expect_words(3);
      if (words[1] != "ascii" && words[1] != "binary_little_endian" &&
          words[1] != "binary_big_endian")
        fail("unknown PLY format '" + words[1] + "'");
      if (words[2] != "1.0") fail("PLY version '" + words[2] + "' (only 1.0 exists)");
      binary = words[1].rfind("binary", 0) == 0;
    } else if (keyword == "comment" || keyword == "obj_info") {
      continue;
    } else if (keyword == "element") {
      expect_words(3);
      ++elements;
      const std::string& name = words[1];
      const std::string& count = words[2];
      char* end = nullptr;
      errno = 0;
      const long long value = std::strtoll(count.c_str(), &end, 10);
      if (end == count.c_str() || *end != '\0')
        fail("element '" + name + "' count '" + count + "' is not a number");
      if (value < 0) fail("element '" + name + "' count " + count + " is negative");
      if (errno == ERANGE || uintmax_t(value) > size)
        fail("element '" + name + "' count " + count + " is more than the file's " +
             std::to_string(size) + " bytes can hold");
      element_count = uintmax_t(value);
    } else if (keyword == "property") {
      if (elements == 0) fail("a property before any element");
      if (words.size() > 1 && words[1] == "list") {
        expect_words(5);
        if (ply_type_size(words[2]) == 0 || ply_type_size(words[3]) == 0)
          fail("unknown list property types '" + words[2] + "' '" + words[3] + "'");
        add(ply_type_size(words[2]) + 3 * ply_type_size(words[3]));
      } else {
        expect_words(3);
        if (ply_type_size(words[1]) == 0) fail("unknown property type '" + words[1] + "'");
        add(ply_type_size(words[1]));
      }
    } else if (keyword == "end_header") {
      expect_words(1);
      break;
    } else {
      fail("unexpected '" + keyword + "' in the PLY header");
    }
  }
  // OpenMesh's reader loops forever looking for the end of such a header.
  if (!in) fail("the header has no end_header line");
  if (!binary) return;
  const uintmax_t header = uintmax_t(in.tellg());
  if (size < header + minimum)
    throw SceneError(where + ": truncated binary PLY '" + path + "': its header needs at least " +
                     std::to_string(header + minimum) + " bytes, the file has " +
                     std::to_string(size));
}

// An OM file starts with "OM", mesh type, version, then vertex, face and edge counts (uint32,
// little endian); a file that yields fewer than it promises was cut short.
void check_om_counts(const std::string& path, const std::string& where, size_t vertices,
                     size_t faces) {
  std::ifstream in(path, std::ios::binary);
  unsigned char header[16] = {};
  in.read(reinterpret_cast<char*>(header), sizeof header);
  if (in.gcount() < std::streamsize(sizeof header) || header[0] != 'O' || header[1] != 'M')
    throw SceneError(where + ": mesh file '" + path + "' is not an OM file or is truncated");
  auto word = [&](int at) {
    return uint32_t(header[at]) | uint32_t(header[at + 1]) << 8 | uint32_t(header[at + 2]) << 16 |
           uint32_t(header[at + 3]) << 24;
  };
  if (vertices < word(4) || faces < word(8))
    throw SceneError(where + ": truncated OM file '" + path + "': header promises " +
                     std::to_string(word(4)) + " vertices and " + std::to_string(word(8)) +
                     " faces, the file holds " + std::to_string(vertices) + " and " +
                     std::to_string(faces));
}

// OpenMesh reports through its own error stream. Its connect() allocates a wrapper that
// disconnect() never frees, so the stream is connected once, to a router that forwards to
// std::cerr except while a load captures it.
class OpenMeshErrorRouter : public std::streambuf {
 public:
  static OpenMeshErrorRouter& instance() {
    static OpenMeshErrorRouter* router = [] {
      auto* r = new OpenMeshErrorRouter;  // lives as long as OpenMesh's stream may use it
      static std::ostream stream(r);
      ::omerr().connect(stream);
      ::omerr().disconnect(std::cerr);
      return r;
    }();
    return *router;
  }
  void route_to(std::streambuf* target) { target_ = target; }

 private:
  int overflow(int c) override { return c == EOF ? c : target_->sputc(char(c)); }
  std::streamsize xsputn(const char* s, std::streamsize n) override { return target_->sputn(s, n); }
  std::streambuf* target_ = std::cerr.rdbuf();
};

// Collects what OpenMesh reports during a load instead of printing it.
class CapturedOpenMeshLog {
 public:
  CapturedOpenMeshLog() : lock_(mutex_) {
    OpenMeshErrorRouter::instance().route_to(text_.rdbuf());
    ::omlog().disable();
    ::omout().disable();
  }
  ~CapturedOpenMeshLog() {
    ::omerr().flush();
    OpenMeshErrorRouter::instance().route_to(std::cerr.rdbuf());
    ::omlog().enable();
    ::omout().enable();
  }
  std::string text() {
    ::omerr().flush();
    return text_.str();
  }

 private:
  static inline std::mutex mutex_;
  std::lock_guard<std::mutex> lock_;
  std::ostringstream text_;
};

}  // namespace

Mesh read_mesh_file(const std::string& path, float crease_angle_deg, const std::string& where,
                    std::vector<std::string>& warnings) {
  if (const std::string problem = input_file_problem(path); !problem.empty())
    throw SceneError(where + ": mesh file '" + path + "' " + problem);
  {
    std::ifstream probe(path, std::ios::binary);
    if (!probe)
      throw SceneError(where + ": cannot read mesh file '" + path + "': " + std::strerror(errno));
  }
  const std::string extension = lowercase_extension(path);
  if (extension != ".obj" && extension != ".ply" && extension != ".off" && extension != ".stl" &&
      extension != ".om")
    throw SceneError(where + ": mesh file '" + path + "' has an unsupported extension '" +
                     extension + "' (expected .obj, .ply, .off, .stl or .om)");
  size_t repeated_vertex_faces = 0;
  if (extension == ".obj") repeated_vertex_faces = check_obj_text(path, where);
  if (extension == ".stl") check_binary_stl_size(path, where);
  if (extension == ".ply") check_ply_header(path, where);

  OpenMeshTriangles om;
  om.request_vertex_normals();
  om.request_vertex_texcoords2D();
  om.request_halfedge_texcoords2D();
  OpenMesh::IO::Options options;
  options += OpenMesh::IO::Options::VertexNormal;
  options += OpenMesh::IO::Options::VertexTexCoord;
  options += OpenMesh::IO::Options::FaceTexCoord;
  std::string log;
  bool ok = false;
  {
    CapturedOpenMeshLog capture;
    try {
      ok = OpenMesh::IO::read_mesh(om, path, options);
    } catch (const std::exception& e) {
      throw SceneError(where + ": cannot read mesh file '" + path + "': " + e.what());
    }
    log = capture.text();
  }
  if (!ok) {
    const std::string reason = first_line(log);
    throw SceneError(where + ": cannot read mesh file '" + path +
                     "': " + (reason.empty() ? "malformed or truncated" : reason));
  }
  if (log.find("invalid vertex index") != std::string::npos)
    throw SceneError(where + ": mesh file '" + path +
                     "' has a face whose vertex index is out of range");
  if (extension == ".om") check_om_counts(path, where, om.n_vertices(), om.n_faces());
  if (om.n_faces() == 0)
    throw SceneError(where + ": mesh file '" + path + "' holds no triangles (empty mesh)");
  for (const auto& vh : om.vertices()) {
    const auto p = om.point(vh);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      throw SceneError(where + ": mesh file '" + path + "': vertex " + std::to_string(vh.idx()) +
                       " has a NaN or infinite coordinate");
  }
  if (const size_t dropped =
          std::max(repeated_vertex_faces, count_occurrences(log, "equal vertices")))
    warnings.push_back(where + ": mesh file '" + path + "': dropped " + std::to_string(dropped) +
                       " face(s) that repeat a vertex (degenerate)");

  const bool halfedge_uvs = options.check(OpenMesh::IO::Options::FaceTexCoord);
  const bool vertex_uvs = options.check(OpenMesh::IO::Options::VertexTexCoord);
  const bool file_normals = options.check(OpenMesh::IO::Options::VertexNormal);
  Mesh mesh;
  // One output vertex per (file vertex, UV) pair: UV seams split vertices, nothing else does.
  std::map<std::tuple<int, float, float>, uint32_t> index_of;
  for (const auto& fh : om.faces()) {
    uvec3 triangle;
    int corner = 0;
    for (const auto& heh : om.fh_range(fh)) {
      if (corner == 3) break;  // TriMesh faces have three corners
      const auto vh = om.to_vertex_handle(heh);
      vec2 uv(0.0f);
      // Mesh files put v = 0 at the image's bottom; the scene (glTF) at its top.
      if (halfedge_uvs) {
        const auto t = om.texcoord2D(heh);
        uv = vec2(t[0], 1.0f - t[1]);
      } else if (vertex_uvs) {
        const auto t = om.texcoord2D(vh);
        uv = vec2(t[0], 1.0f - t[1]);
      }
      const auto [it, inserted] =
          index_of.try_emplace({vh.idx(), uv.x, uv.y}, uint32_t(mesh.positions.size()));
      if (inserted) {
        const auto p = om.point(vh);
        mesh.positions.push_back(vec3(p[0], p[1], p[2]));
        if (file_normals) {
          const auto n = om.normal(vh);
          mesh.normals.push_back(vec3(n[0], n[1], n[2]));
        }
        if (halfedge_uvs || vertex_uvs) mesh.uvs.push_back(uv);
      }
      triangle[corner++] = it->second;
    }
    mesh.triangles.push_back(triangle);
  }
  if (!file_normals) compute_normals(mesh, crease_angle_deg);
  return mesh;
}

}  // namespace lb

/*
 * gltf_guard.cpp: what a glTF may ask of the importers, checked before any
 * of them parses it (assimp's and tinygltf's parsers recurse, allocate what
 * a header claims and read whatever a URI names): the files it names, the
 * .glb's chunks, its JSON's nesting and base64, the node forest and the
 * triangles its instances add up to. The policy; gltf_shim.cpp the readers.
 */
#include "gltf_guard.h"
#include "shim.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <string>
#include <vector>

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/vfs.h>
#include <unistd.h>

namespace
{
// The strengths need only the JSON: images are not decoded.
bool skip_image(tinygltf::Image *, const int, std::string *, std::string *, int, int,
                const unsigned char *, int, void *)
{
    return true;
}

bool ends_with(const std::string &s, const char *tail)
{
    const size_t n = std::strlen(tail);
    return s.size() >= n && s.compare(s.size() - n, n, tail) == 0;
}

// A file a scene names: only a regular file outside procfs and sysfs (whose files claim
// to be regular and never end), opened without blocking, of at most `limit` bytes.
bool read_regular(std::vector<unsigned char> *out, std::string *err, const std::string &path,
                  uint64_t limit)
{
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    struct stat st;
    struct statfs fs;
    if (fd < 0 || fstat(fd, &st) != 0 || fstatfs(fd, &fs) != 0) {
        *err = "'" + path + "': cannot open: " + std::strerror(errno);
        if (fd >= 0)
            ::close(fd);
        return false;
    }
    const bool pseudo = fs.f_type == 0x9fa0 /* procfs */ || fs.f_type == 0x62656572 /* sysfs */;
    if (!S_ISREG(st.st_mode) || pseudo) {
        *err = "'" + path + "' is not a regular file (a pipe, device or /proc file is never read)";
        ::close(fd);
        return false;
    }
    if (uint64_t(st.st_size) > limit) {
        *err = "'" + path + "' holds " + std::to_string(st.st_size) + " bytes, over the limit of " +
               std::to_string(limit);
        ::close(fd);
        return false;
    }
    out->resize(size_t(st.st_size));
    size_t got = 0;
    while (got < out->size()) {
        const ssize_t n = ::read(fd, out->data() + got, out->size() - got);
        if (n <= 0)
            break;
        got += size_t(n);
    }
    ::close(fd);
    if (got != out->size()) {
        *err = "'" + path + "': cannot read it whole";
        return false;
    }
    return true;
}

bool fs_exists(const std::string &path, void *)
{
    struct stat st;
    return ::stat(path.c_str(), &st) == 0;
}

std::string fs_expand(const std::string &path, void *)
{
    return path; // no ~ or $VAR expansion: a scene names files, not shells
}

bool fs_read(std::vector<unsigned char> *out, std::string *err, const std::string &path, void *)
{
    return read_regular(out, err, path, VDBGI_GLTF_MAX_BUFFER);
}

bool fs_write(std::string *err, const std::string &, const std::vector<unsigned char> &, void *)
{
    *err = "writing is not for a reader";
    return false;
}

// How deep JSON text nests arrays and objects (outside strings): recursive parsers
// (assimp's, tinygltf's) overflow the stack long before memory runs out.
size_t json_depth(const unsigned char *p, size_t n)
{
    size_t depth = 0, deepest = 0;
    bool in_string = false;
    for (size_t i = 0; i < n; i++) {
        const unsigned char c = p[i];
        if (in_string) {
            if (c == '\\')
                i++;
            else if (c == '"')
                in_string = false;
        } else if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            deepest = std::max(deepest, ++depth);
        } else if ((c == ']' || c == '}') && depth) {
            depth--;
        }
    }
    return deepest;
}

uint32_t le32(const unsigned char *p)
{
    return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

// A .glb's 12-byte header and chunk table against the file: where its JSON lies.
bool glb_json(const std::vector<unsigned char> &f, size_t *begin, size_t *size, std::string *err)
{
    if (f.size() < 20) {
        *err = "a .glb shorter than its 20-byte header";
        return false;
    }
    const uint32_t length = le32(&f[8]), json = le32(&f[12]);
    if (le32(&f[4]) != 2) {
        *err = "glb version " + std::to_string(le32(&f[4])) + ", not 2";
        return false;
    }
    if (length != f.size()) {
        *err = "the .glb header says " + std::to_string(length) + " bytes, the file holds " +
               std::to_string(f.size());
        return false;
    }
    if (json > f.size() - 20 || le32(&f[16]) != 0x4E4F534Au) {
        *err = "the .glb's JSON chunk claims " + std::to_string(json) + " bytes of " +
               std::to_string(f.size() - 20) + " left, or is not JSON";
        return false;
    }
    const size_t bin = 20 + size_t(json);
    if (bin + 8 <= f.size() && uint64_t(le32(&f[bin])) > f.size() - bin - 8) {
        *err = "the .glb's binary chunk claims " + std::to_string(le32(&f[bin])) + " bytes of " +
               std::to_string(f.size() - bin - 8) + " left";
        return false;
    }
    *begin = 20;
    *size = json;
    return true;
}

// Every data: URI's base64 in the JSON text, strictly (RFC 4648): the alphabet, and '='
// only as the last one or two of a length that is a multiple of 4. tinygltf decodes an
// image's leniently (and keeps no URI to check), so a damaged one loads as other bytes.
bool strict_base64(const unsigned char *json, size_t n, std::string *err)
{
    static const char mark[] = "\"data:";
    for (size_t i = 0; i + sizeof(mark) - 1 < n; i++) {
        if (std::memcmp(&json[i], mark, sizeof(mark) - 1) != 0)
            continue;
        std::string uri; // JSON may escape '/' with a backslash
        size_t end = i + 1;
        for (; end < n && json[end] != '"'; end++) {
            if (json[end] == '\\' && end + 1 < n && json[end + 1] == '/')
                end++;
            uri += char(json[end]);
        }
        i = end;
        const size_t at = uri.find(";base64,");
        if (at == std::string::npos)
            continue;
        const size_t begin = at + 8;
        bool ok = (uri.size() - begin) % 4 == 0;
        for (size_t k = begin; ok && k < uri.size(); k++) {
            const unsigned char c = static_cast<unsigned char>(uri[k]);
            const bool pad =
                c == '=' && k + 2 >= uri.size() && (k + 1 == uri.size() || uri[k + 1] == '=');
            ok = std::isalnum(c) || c == '+' || c == '/' || pad;
        }
        if (!ok) {
            *err = "a data: URI (" + uri.substr(0, std::min<size_t>(at, 40)) +
                   ") is not strict base64";
            return false;
        }
    }
    return true;
}

// Triangles one mesh adds each time a node instances it.
uint64_t mesh_triangles(const tinygltf::Model &m, int mesh)
{
    uint64_t t = 0;
    for (const tinygltf::Primitive &p : m.meshes[size_t(mesh)].primitives) {
        const auto pos = p.attributes.find("POSITION");
        const int a = p.indices >= 0 ? p.indices : pos != p.attributes.end() ? pos->second : -1;
        if (a >= 0 && size_t(a) < m.accessors.size())
            t += m.accessors[size_t(a)].count / 3;
    }
    return t;
}

// The node forest: every index in range, no node with two parents or under itself, at
// most VDBGI_GLTF_MAX_NODE_DEPTH deep, and its instances' triangles within the budget.
bool check_nodes(const tinygltf::Model &m, std::string *err)
{
    const size_t n = m.nodes.size();
    std::vector<int> parent(n, -1);
    for (size_t i = 0; i < n; i++)
        for (int c : m.nodes[i].children) {
            if (c < 0 || size_t(c) >= n) {
                *err = "node " + std::to_string(i) + " has child " + std::to_string(c) + " of " +
                       std::to_string(n) + " nodes";
                return false;
            }
            if (parent[size_t(c)] >= 0 || size_t(c) == i) {
                *err = "node " + std::to_string(c) + " has two parents, or is its own";
                return false;
            }
            parent[size_t(c)] = int(i);
        }
    uint64_t triangles = 0;
    std::vector<std::pair<size_t, size_t>> stack; // node, depth
    for (size_t i = 0; i < n; i++)
        if (parent[i] < 0)
            stack.emplace_back(i, 1);
    size_t seen = 0;
    while (!stack.empty()) {
        const auto [node, depth] = stack.back();
        stack.pop_back();
        seen++;
        if (depth > VDBGI_GLTF_MAX_NODE_DEPTH) {
            *err = "nodes nest more than " + std::to_string(VDBGI_GLTF_MAX_NODE_DEPTH) + " deep";
            return false;
        }
        const int mesh = m.nodes[node].mesh;
        if (mesh >= 0 && size_t(mesh) < m.meshes.size())
            triangles += mesh_triangles(m, mesh);
        if (triangles > VDBGI_GLTF_MAX_TRIANGLES) {
            *err = "its instances add up to more than " + std::to_string(VDBGI_GLTF_MAX_TRIANGLES) +
                   " triangles";
            return false;
        }
        for (int c : m.nodes[node].children)
            stack.emplace_back(size_t(c), depth + 1);
    }
    if (seen != n) { // a cycle: its nodes have parents but no root reaches them
        *err = "its nodes form a cycle";
        return false;
    }
    return true;
}
} // namespace

void vdbgi_gltf_guard_files(tinygltf::TinyGLTF &loader)
{
    tinygltf::FsCallbacks fs = {fs_exists, fs_expand, fs_read, fs_write, nullptr};
    loader.SetFsCallbacks(fs);
    loader.SetImageLoader(skip_image, nullptr);
}

bool vdbgi_gltf_named(const char *path, const char *ext)
{
    std::string name(path);
    for (char &c : name)
        c = char(std::tolower(static_cast<unsigned char>(c)));
    return ends_with(name, ext);
}

/* The checks above in order: true, with the first refusal's reason in *why, when one fails. */
static bool refused(const char *path, std::string *why)
{
    std::vector<unsigned char> file;
    if (!read_regular(&file, why, path, VDBGI_GLTF_MAX_BUFFER))
        return true;
    const bool glb = file.size() >= 4 && std::memcmp(file.data(), "glTF", 4) == 0;
    if (!glb && !vdbgi_gltf_named(path, ".gltf"))
        return false;
    size_t begin = 0, size = file.size();
    if (glb && !glb_json(file, &begin, &size, why))
        return true;
    if (!strict_base64(&file[begin], size, why))
        return true;
    const size_t depth = json_depth(&file[begin], size);
    if (depth > VDBGI_GLTF_MAX_NESTING) {
        *why = "its JSON nests " + std::to_string(depth) + " deep (more than " +
               std::to_string(VDBGI_GLTF_MAX_NESTING) + ")";
        return true;
    }
    tinygltf::Model m;
    tinygltf::TinyGLTF loader;
    vdbgi_gltf_guard_files(loader);
    const std::string p(path);
    const size_t slash = p.rfind('/');
    const std::string dir = slash == std::string::npos ? "." : p.substr(0, slash);
    std::string error, warning;
    const bool ok = glb ? loader.LoadBinaryFromMemory(&m, &error, &warning, file.data(),
                                                      unsigned(file.size()), dir)
                        : loader.LoadASCIIFromString(&m, &error, &warning,
                                                     reinterpret_cast<const char *>(file.data()),
                                                     unsigned(file.size()), dir);
    if (!ok) {
        *why = error.empty() ? "tinygltf cannot read it" : error;
        return true;
    }
    return !check_nodes(m, why);
}

extern "C" vdbgi_result vdbgi_gltf_precheck(vdbgi_context *ctx, const char *path)
{
    VDBGI_SHIM_BEGIN
    std::string why;
    if (refused(path, &why))
        return vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: %s", path, why.c_str());
    return VDBGI_OK;
    VDBGI_SHIM_END_FILE(ctx, "glTF", path)
}

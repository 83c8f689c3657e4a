/*
 * gltf_shim.cpp: a binary glTF (.glb) through tinygltf, built from plain C
 * arrays. Lightmaps travel in each material's extras ("vdbgi_lightmap":
 * texture index, texCoord 1, scale), since glTF has no lightmap slot;
 * AO maps are the core occlusionTexture on texCoord 1.
 */
#include "gltf_shim.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <fstream>
#include <sstream>
#include <vector>

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/vfs.h>
#include <unistd.h>

namespace
{

// Append bytes to the one buffer as a view of their own, 4-byte aligned.
int add_view(tinygltf::Model &m, const void *data, size_t size, int target)
{
    std::vector<unsigned char> &buf = m.buffers[0].data;
    while (buf.size() % 4)
        buf.push_back(0);
    tinygltf::BufferView v;
    v.buffer = 0;
    v.byteOffset = buf.size();
    v.byteLength = size;
    v.target = target;
    const unsigned char *p = static_cast<const unsigned char *>(data);
    buf.insert(buf.end(), p, p + size);
    m.bufferViews.push_back(v);
    return int(m.bufferViews.size() - 1);
}

int add_accessor(tinygltf::Model &m, const float *data, size_t count, int components, bool bounds)
{
    tinygltf::Accessor a;
    a.bufferView =
        add_view(m, data, count * components * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER);
    a.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
    a.count = count;
    a.type = components == 3 ? TINYGLTF_TYPE_VEC3 : TINYGLTF_TYPE_VEC2;
    if (bounds) { // POSITION must carry min and max
        a.minValues.assign(components, 1e30);
        a.maxValues.assign(components, -1e30);
        for (size_t i = 0; i < count; i++)
            for (int k = 0; k < components; k++) {
                a.minValues[k] = std::min(a.minValues[k], double(data[i * components + k]));
                a.maxValues[k] = std::max(a.maxValues[k], double(data[i * components + k]));
            }
    }
    m.accessors.push_back(a);
    return int(m.accessors.size() - 1);
}

int add_texture(tinygltf::Model &m, int image, int sampler)
{
    tinygltf::Texture t;
    t.source = image;
    t.sampler = sampler;
    m.textures.push_back(t);
    return int(m.textures.size() - 1);
}

// Run body, an exception becoming a message in err: no C++ exception crosses into C.
template <class Body> bool guarded(char *err, size_t err_size, Body body)
{
    try {
        return body();
    } catch (const std::exception &e) {
        std::snprintf(err, err_size, "glTF: %s", e.what());
    } catch (...) {
        std::snprintf(err, err_size, "glTF: unknown error");
    }
    return false;
}

} // namespace

/*
 * tinygltf's model filled in one place (about 130 lines, kept whole): every
 * buffer view, accessor, texture and material refers by index to the ones
 * made before it, which reads best as one sequence.
 */
extern "C" bool vdbgi_gltf_encode(const vdbgi_gltf_desc *d, uint8_t **out, size_t *size, char *err,
                                  size_t err_size)
{
    *out = nullptr;
    *size = 0;
    return guarded(err, err_size, [&]() -> bool {
        tinygltf::Model m;
        m.asset.version = "2.0";
        m.asset.generator = d->generator ? d->generator : "vdbgi";
        m.buffers.resize(1);
        tinygltf::Sampler s; // linear, clamped: the maps' gutters are made for it
        s.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
        s.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
        s.wrapS = s.wrapT = TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
        m.samplers.push_back(s);
        s.wrapS = s.wrapT = TINYGLTF_TEXTURE_WRAP_REPEAT; // base colour tiles, as the bake read it
        m.samplers.push_back(s);
        for (size_t i = 0; i < d->image_count; i++) {
            tinygltf::Image im;
            im.mimeType = "image/png";
            im.bufferView = add_view(m, d->images[i].png, d->images[i].size, 0);
            m.images.push_back(im);
        }
        bool strength_used = false;
        for (size_t i = 0; i < d->material_count; i++) {
            const vdbgi_gltf_material &src = d->materials[i];
            tinygltf::Material mat;
            mat.pbrMetallicRoughness.baseColorFactor = {src.base[0], src.base[1], src.base[2], 1.0};
            mat.pbrMetallicRoughness.metallicFactor = 0.0;
            mat.pbrMetallicRoughness.roughnessFactor = 1.0;
            mat.doubleSided = src.double_sided;
            if (src.base_texture >= 0) {
                mat.pbrMetallicRoughness.baseColorTexture.index =
                    add_texture(m, src.base_texture, 1);
                mat.pbrMetallicRoughness.baseColorTexture.texCoord = 0;
            }
            const float peak = std::max({src.emissive[0], src.emissive[1], src.emissive[2]});
            if (peak > 0.0f) {
                const float f = peak > 1.0f ? peak : 1.0f;
                mat.emissiveFactor = {src.emissive[0] / f, src.emissive[1] / f,
                                      src.emissive[2] / f};
                if (f > 1.0f) {
                    tinygltf::Value::Object strength;
                    strength["emissiveStrength"] = tinygltf::Value(double(f));
                    mat.extensions["KHR_materials_emissive_strength"] = tinygltf::Value(strength);
                    strength_used = true;
                }
                if (src.emissive_texture >= 0) {
                    mat.emissiveTexture.index = add_texture(m, src.emissive_texture, 1);
                    mat.emissiveTexture.texCoord = 0;
                }
            }
            if (src.map >= 0) {
                const int tex = add_texture(m, src.map, 0);
                if (d->ao) {
                    mat.occlusionTexture.index = tex;
                    mat.occlusionTexture.texCoord = 1;
                } else {
                    tinygltf::Value::Object lm;
                    lm["texture"] = tinygltf::Value(tex);
                    lm["texCoord"] = tinygltf::Value(1);
                    lm["scale"] = tinygltf::Value(double(d->map_scale));
                    tinygltf::Value::Array layers;
                    for (size_t l = 0; src.layer_maps && l < d->layer_count; l++) {
                        tinygltf::Value::Object layer;
                        layer["name"] = tinygltf::Value(std::string(d->layer_names[l]));
                        layer["texture"] = tinygltf::Value(add_texture(m, src.layer_maps[l], 0));
                        layer["scale"] = tinygltf::Value(double(d->layer_scales[l]));
                        layers.push_back(tinygltf::Value(layer));
                    }
                    if (!layers.empty())
                        lm["layers"] = tinygltf::Value(layers);
                    tinygltf::Value::Object extras;
                    extras["vdbgi_lightmap"] = tinygltf::Value(lm);
                    mat.extras = tinygltf::Value(extras);
                }
            }
            m.materials.push_back(mat);
        }
        if (strength_used)
            m.extensionsUsed.push_back("KHR_materials_emissive_strength");
        const int pos = add_accessor(m, d->positions, d->vertex_count, 3, true);
        const int nrm = add_accessor(m, d->normals, d->vertex_count, 3, false);
        const int uv0 = d->uv0 ? add_accessor(m, d->uv0, d->vertex_count, 2, false) : -1;
        const int uv1 = add_accessor(m, d->uv1, d->vertex_count, 2, false);
        const int col = d->colors ? add_accessor(m, d->colors, d->vertex_count, 3, false) : -1;
        tinygltf::Mesh mesh;
        for (size_t i = 0; i < d->primitive_count; i++) {
            const vdbgi_gltf_primitive &p = d->primitives[i];
            // Each primitive reads its own range of the shared vertex arrays through indices.
            std::vector<uint32_t> idx(p.count);
            for (uint32_t k = 0; k < p.count; k++)
                idx[k] = p.first + k;
            tinygltf::Accessor ia;
            ia.bufferView =
                add_view(m, idx.data(), idx.size() * 4, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
            ia.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
            ia.count = idx.size();
            ia.type = TINYGLTF_TYPE_SCALAR;
            m.accessors.push_back(ia);
            tinygltf::Primitive prim;
            prim.attributes["POSITION"] = pos;
            prim.attributes["NORMAL"] = nrm;
            if (uv0 >= 0)
                prim.attributes["TEXCOORD_0"] = uv0;
            prim.attributes["TEXCOORD_1"] = uv1;
            if (col >= 0)
                prim.attributes["COLOR_0"] = col;
            prim.indices = int(m.accessors.size() - 1);
            prim.material = int(p.material);
            prim.mode = TINYGLTF_MODE_TRIANGLES;
            mesh.primitives.push_back(prim);
        }
        m.meshes.push_back(mesh);
        tinygltf::Node node;
        node.mesh = 0;
        m.nodes.push_back(node);
        tinygltf::Scene scene;
        scene.nodes.push_back(0);
        m.scenes.push_back(scene);
        m.defaultScene = 0;
        std::ostringstream os;
        tinygltf::TinyGLTF writer;
        if (!writer.WriteGltfSceneToStream(&m, os, false, true)) {
            std::snprintf(err, err_size, "tinygltf could not write the .glb");
            return false;
        }
        const std::string bytes = os.str();
        *out = static_cast<uint8_t *>(std::malloc(bytes.size() ? bytes.size() : 1));
        if (!*out) {
            std::snprintf(err, err_size, "out of memory for a %zu-byte .glb", bytes.size());
            return false;
        }
        std::memcpy(*out, bytes.data(), bytes.size());
        *size = bytes.size();
        return true;
    });
}

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

bool has_extension(const char *path, const char *ext)
{
    std::string name(path);
    for (char &c : name)
        c = char(std::tolower(static_cast<unsigned char>(c)));
    return ends_with(name, ext);
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

// The files a glTF names, through our checks: never a FIFO, device or /proc file.
void guard_files(tinygltf::TinyGLTF &loader)
{
    tinygltf::FsCallbacks fs = {fs_exists, fs_expand, fs_read, fs_write, nullptr};
    loader.SetFsCallbacks(fs);
    loader.SetImageLoader(skip_image, nullptr);
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

extern "C" bool vdbgi_gltf_precheck(const char *path, char *err, size_t err_size)
{
    return guarded(err, err_size, [&]() -> bool {
        std::vector<unsigned char> file;
        std::string why;
        const auto fail = [&](const std::string &w) {
            std::snprintf(err, err_size, "%s", w.c_str());
            return false;
        };
        if (!read_regular(&file, &why, path, VDBGI_GLTF_MAX_BUFFER))
            return fail(why);
        const bool glb = file.size() >= 4 && std::memcmp(file.data(), "glTF", 4) == 0;
        if (!glb && !has_extension(path, ".gltf"))
            return true;
        size_t begin = 0, size = file.size();
        if (glb && !glb_json(file, &begin, &size, &why))
            return fail(why);
        if (!strict_base64(&file[begin], size, &why))
            return fail(why);
        const size_t depth = json_depth(&file[begin], size);
        if (depth > VDBGI_GLTF_MAX_NESTING)
            return fail("its JSON nests " + std::to_string(depth) + " deep (more than " +
                        std::to_string(VDBGI_GLTF_MAX_NESTING) + ")");
        tinygltf::Model m;
        tinygltf::TinyGLTF loader;
        guard_files(loader);
        const std::string p(path);
        const size_t slash = p.rfind('/');
        const std::string dir = slash == std::string::npos ? "." : p.substr(0, slash);
        std::string error, warning;
        const bool ok = glb ? loader.LoadBinaryFromMemory(&m, &error, &warning, file.data(),
                                                          unsigned(file.size()), dir)
                            : loader.LoadASCIIFromString(
                                  &m, &error, &warning, reinterpret_cast<const char *>(file.data()),
                                  unsigned(file.size()), dir);
        if (!ok)
            return fail(error.empty() ? "tinygltf cannot read it" : error);
        return check_nodes(m, &why) ? true : fail(why);
    });
}

/* The glTF at path (by its name) into m; false for another kind (none) or, with err set, a
   file that does not parse. */
static bool load_model(const char *path, tinygltf::Model &m, char *err, size_t err_size)
{
    std::string name(path);
    for (char &c : name)
        c = char(std::tolower(static_cast<unsigned char>(c)));
    const bool glb = ends_with(name, ".glb"), gltf = ends_with(name, ".gltf");
    if (!glb && !gltf)
        return false;
    tinygltf::TinyGLTF loader;
    guard_files(loader);
    std::string error, warning;
    const bool ok = glb ? loader.LoadBinaryFromFile(&m, &error, &warning, path)
                        : loader.LoadASCIIFromFile(&m, &error, &warning, path);
    if (!ok)
        std::snprintf(err, err_size, "%s",
                      error.empty() ? "tinygltf cannot read it" : error.c_str());
    return ok;
}

extern "C" bool vdbgi_gltf_light_ranges(const char *path, float **out, size_t *count, char *err,
                                        size_t err_size)
{
    *out = nullptr;
    *count = 0;
    return guarded(err, err_size, [&]() -> bool {
        tinygltf::Model m;
        err[0] = '\0';
        if (!load_model(path, m, err, err_size))
            return err[0] == '\0';
        if (m.lights.empty())
            return true;
        float *const r = static_cast<float *>(std::calloc(m.lights.size(), sizeof(float)));
        if (!r) {
            std::snprintf(err, err_size, "out of memory for %zu lights", m.lights.size());
            return false;
        }
        for (size_t i = 0; i < m.lights.size(); i++) {
            const double v = m.lights[i].range;
            r[i] = v > 3e38 ? HUGE_VALF : v < -3e38 ? -HUGE_VALF : float(v);
        }
        *out = r;
        *count = m.lights.size();
        return true;
    });
}

extern "C" bool vdbgi_gltf_materials(const char *path, vdbgi_gltf_material_info **out,
                                     size_t *count, char *err, size_t err_size)
{
    *out = nullptr;
    *count = 0;
    return guarded(err, err_size, [&]() -> bool {
        tinygltf::Model m;
        err[0] = '\0';
        if (!load_model(path, m, err, err_size))
            return err[0] == '\0';
        if (m.materials.empty())
            return true;
        vdbgi_gltf_material_info *const info = static_cast<vdbgi_gltf_material_info *>(
            std::calloc(m.materials.size(), sizeof(vdbgi_gltf_material_info)));
        if (!info) {
            std::snprintf(err, err_size, "out of memory for %zu materials", m.materials.size());
            return false;
        }
        for (size_t i = 0; i < m.materials.size(); i++) {
            const tinygltf::Material &src = m.materials[i];
            vdbgi_gltf_material_info &o = info[i];
            o = vdbgi_gltf_material_info{};
            if (src.name.size() < sizeof(o.name))
                std::memcpy(o.name, src.name.c_str(), src.name.size() + 1);
            for (int k = 0; k < 3; k++) {
                o.emissive[k] =
                    k < int(src.emissiveFactor.size()) ? float(src.emissiveFactor[k]) : 0.0f;
                const auto &b = src.pbrMetallicRoughness.baseColorFactor;
                o.base[k] = k < int(b.size()) ? float(b[k]) : 1.0f;
            }
            o.strength = 1.0f;
            const auto ext = src.extensions.find("KHR_materials_emissive_strength");
            if (ext != src.extensions.end()) {
                const tinygltf::Value &v = ext->second.Get("emissiveStrength");
                // As written: the importer refuses a negative one and caps a large one.
                const double d = v.IsNumber() ? v.GetNumberAsDouble() : 1.0;
                o.strength = d > 3e38 ? HUGE_VALF : float(d);
            }
        }
        *out = info;
        *count = m.materials.size();
        return true;
    });
}

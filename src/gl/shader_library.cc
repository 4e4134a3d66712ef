#include "gl/shader_library.h"

#include <algorithm>
#include <regex>
#include <sstream>

#include "core/hash.h"

namespace hdribr::gl {

ShaderLibrary::ShaderLibrary() : ShaderLibrary(EmbeddedShaders()) {}

ShaderLibrary::ShaderLibrary(std::map<std::string, std::string> sources)
    : sources_(std::move(sources)) {
  for (const auto& [name, text] : sources_) names_.push_back(name);
}

int ShaderLibrary::IndexOf(const std::string& name) const {
  const auto it = std::find(names_.begin(), names_.end(), name);
  return it == names_.end() ? -1 : static_cast<int>(it - names_.begin());
}

void ShaderLibrary::Expand(const std::string& name, std::vector<std::string>& stack,
                           std::string& out) const {
  const auto it = sources_.find(name);
  if (it == sources_.end()) throw ShaderError("shader file not found: " + name);
  if (std::find(stack.begin(), stack.end(), name) != stack.end()) {
    throw ShaderError("recursive #include of " + name);
  }
  stack.push_back(name);
  const int index = IndexOf(name);
  static const std::regex kInclude(R"(^\s*#\s*include\s+"([^"]+)\"\s*$)");
  std::istringstream in(it->second);
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    std::smatch m;
    if (std::regex_match(line, m, kInclude)) {
      if (sources_.count(m[1].str()) == 0) {
        throw ShaderError(name + ":" + std::to_string(line_no) + ": #include \"" + m[1].str() +
                          "\": no such shader file");
      }
      out += "#line 1 " + std::to_string(IndexOf(m[1].str())) + "\n";
      Expand(m[1].str(), stack, out);
      out += "#line " + std::to_string(line_no + 1) + " " + std::to_string(index) + "\n";
    } else {
      out += line + "\n";
    }
  }
  stack.pop_back();
}

std::string ShaderLibrary::Preprocess(const std::string& name, const Defines& defines) const {
  std::string body;
  std::vector<std::string> stack;
  Expand(name, stack, body);
  // #version must stay the first line; defines and a #line follow it.
  const size_t version = body.find("#version");
  if (version == std::string::npos) throw ShaderError(name + ":1: missing #version");
  const size_t eol = body.find('\n', version);
  std::string head = body.substr(0, eol + 1);
  for (const auto& [key, value] : defines) head += "#define " + key + " " + value + "\n";
  const int version_line = 1 + static_cast<int>(std::count(body.begin(), body.begin() + eol, '\n'));
  head += "#line " + std::to_string(version_line + 1) + " " + std::to_string(IndexOf(name)) + "\n";
  return head + body.substr(eol + 1);
}

std::string ShaderLibrary::MapLog(const std::string& log) const {
  // Mesa: "3:12(5): error: ..."; NVIDIA: "3(12) : error ...". Replace the source-string
  // number by the file name.
  static const std::regex kLoc(R"((^|\n)(\d+)[:(](\d+)\)?)");
  std::string out;
  auto begin = log.cbegin();
  std::smatch m;
  while (std::regex_search(begin, log.cend(), m, kLoc)) {
    out.append(begin, m[0].first);
    const int idx = std::stoi(m[2].str());
    const std::string file =
        idx >= 0 && idx < static_cast<int>(names_.size()) ? names_[idx] : m[2].str();
    out += m[1].str() + file + ":" + m[3].str();
    begin = m[0].second;
  }
  out.append(begin, log.cend());
  return out;
}

Program ShaderLibrary::Build(const std::vector<std::string>& names, const Defines& defines) const {
  const size_t variant = built_.size();
  built_.push_back({names, defines});
  Program program = Program::Create();
  std::vector<Shader> shaders;
  Fnv1a64 source_hash;
  for (const std::string& name : names) {
    GLenum stage = 0;
    const std::string ext = name.substr(name.find_last_of('.') + 1);
    if (ext == "vert")
      stage = GL_VERTEX_SHADER;
    else if (ext == "frag")
      stage = GL_FRAGMENT_SHADER;
    else if (ext == "comp")
      stage = GL_COMPUTE_SHADER;
    else if (ext == "geom")
      stage = GL_GEOMETRY_SHADER;
    else
      throw ShaderError("unknown shader stage for " + name);
    const std::string src = Preprocess(name, defines);
    source_hash.AddString(src);
    Shader shader(stage);
    const char* ptr = src.c_str();
    glShaderSource(shader.id(), 1, &ptr, nullptr);
    glCompileShader(shader.id());
    GLint ok = 0;
    glGetShaderiv(shader.id(), GL_COMPILE_STATUS, &ok);
    if (!ok) {
      GLint len = 0;
      glGetShaderiv(shader.id(), GL_INFO_LOG_LENGTH, &len);
      std::string log(static_cast<size_t>(std::max(len, 1)), '\0');
      glGetShaderInfoLog(shader.id(), len, nullptr, log.data());
      log.resize(log.find('\0') == std::string::npos ? log.size() : log.find('\0'));
      throw ShaderError("shader compile failed: " + MapLog(log));
    }
    glAttachShader(program.id(), shader.id());
    shaders.push_back(std::move(shader));
  }
  built_[variant].source_hash = source_hash.value();
  glLinkProgram(program.id());
  GLint ok = 0;
  glGetProgramiv(program.id(), GL_LINK_STATUS, &ok);
  if (!ok) {
    GLint len = 0;
    glGetProgramiv(program.id(), GL_INFO_LOG_LENGTH, &len);
    std::string log(static_cast<size_t>(std::max(len, 1)), '\0');
    glGetProgramInfoLog(program.id(), len, nullptr, log.data());
    std::string files;
    for (const auto& n : names) files += (files.empty() ? "" : "+") + n;
    throw ShaderError("shader link failed (" + files + "): " + MapLog(log.c_str()));
  }
  for (const Shader& s : shaders) glDetachShader(program.id(), s.id());
  return program;
}

}  // namespace hdribr::gl

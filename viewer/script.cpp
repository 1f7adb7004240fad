#include "script.h"

#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <GLFW/glfw3.h>

namespace epi::viewer {

namespace {

std::string upper(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = char(std::toupper(static_cast<unsigned char>(c)));
  return out;
}

}  // namespace

int key_code(std::string_view name_view) {
  const std::string name = upper(name_view);
  if (name.size() == 1 && name[0] >= 'A' && name[0] <= 'Z') return GLFW_KEY_A + (name[0] - 'A');
  if (name.size() == 1 && name[0] >= '0' && name[0] <= '9') return GLFW_KEY_0 + (name[0] - '0');
  if (name.size() >= 2 && name.size() <= 3 && name[0] == 'F') {
    int n = 0;
    for (size_t i = 1; i < name.size(); ++i) {
      if (!std::isdigit(static_cast<unsigned char>(name[i]))) return -1;
      n = n * 10 + (name[i] - '0');
    }
    return n >= 1 && n <= 25 ? GLFW_KEY_F1 + n - 1 : -1;
  }
  static const struct {
    const char* name;
    int code;
  } named[] = {{"SPACE", GLFW_KEY_SPACE},       {"ESCAPE", GLFW_KEY_ESCAPE},   {"ENTER", GLFW_KEY_ENTER},
               {"TAB", GLFW_KEY_TAB},           {"BACKSPACE", GLFW_KEY_BACKSPACE}, {"LEFT", GLFW_KEY_LEFT},
               {"RIGHT", GLFW_KEY_RIGHT},       {"UP", GLFW_KEY_UP},           {"DOWN", GLFW_KEY_DOWN},
               {"PAGE_UP", GLFW_KEY_PAGE_UP},   {"PAGE_DOWN", GLFW_KEY_PAGE_DOWN}, {"HOME", GLFW_KEY_HOME},
               {"END", GLFW_KEY_END},           {"LEFT_SHIFT", GLFW_KEY_LEFT_SHIFT}, {"LEFT_CONTROL", GLFW_KEY_LEFT_CONTROL},
               {"MINUS", GLFW_KEY_MINUS},       {"EQUAL", GLFW_KEY_EQUAL}};
  for (const auto& n : named)
    if (name == n.name) return n.code;
  return -1;
}

std::vector<ScriptCommand> parse_script(std::string_view text, const std::string& source) {
  std::vector<ScriptCommand> commands;
  std::istringstream in{std::string(text)};
  std::string line_text;
  int line = 0;
  while (std::getline(in, line_text)) {
    ++line;
    if (const size_t hash = line_text.find('#'); hash != std::string::npos) line_text.resize(hash);
    std::istringstream words(line_text);
    std::string word;
    if (!(words >> word)) continue;
    auto fail = [&](const std::string& problem) -> std::runtime_error {
      return std::runtime_error(source + ":" + std::to_string(line) + ": " + problem);
    };
    auto number = [&](const char* what) {
      std::string w;
      if (!(words >> w)) throw fail("'" + word + "' needs " + what);
      try {
        size_t used = 0;
        const float v = std::stof(w, &used);
        if (used != w.size() || !std::isfinite(v) || std::abs(v) > 1e6f) throw std::invalid_argument(w);
        return v;
      } catch (const std::exception&) {
        throw fail("'" + word + "': " + what + " must be a finite number, got '" + w + "'");
      }
    };
    auto count = [&](const char* what) {
      const float v = number(what);
      if (v < 0.0f || v != std::floor(v)) throw fail("'" + word + "': " + what + " must be a whole number >= 0");
      return int(v);
    };
    auto button = [&] {
      std::string b;
      if (!(words >> b)) throw fail("'" + word + "' needs a button (left, middle or right)");
      if (b == "left") return Button::left;
      if (b == "middle") return Button::middle;
      if (b == "right") return Button::right;
      throw fail("unknown button '" + b + "' (left, middle or right)");
    };
    auto key = [&](ScriptCommand& c) {
      std::string k;
      if (!(words >> k)) throw fail("'" + word + "' needs a key name");
      c.name = k;
      std::string rest = upper(k);
      for (bool more = true; more;) {
        more = false;
        for (const auto& [prefix, bit] : {std::pair{"CTRL+", GLFW_MOD_CONTROL}, {"SHIFT+", GLFW_MOD_SHIFT}, {"ALT+", GLFW_MOD_ALT}})
          if (rest.rfind(prefix, 0) == 0) rest = rest.substr(std::string(prefix).size()), c.mods |= bit, more = true;
      }
      c.key = key_code(rest);
      if (c.key < 0) throw fail("unknown key '" + k + "' (a GLFW key name, e.g. F, ESCAPE, F3, 1, CTRL+1)");
    };
    ScriptCommand c;
    c.line = line;
    using K = ScriptCommand::Kind;
    if (word == "wait") {
      c.kind = K::wait, c.frames = count("a frame count");
    } else if (word == "key") {
      c.kind = K::key, key(c);
    } else if (word == "hold") {
      c.kind = K::hold, key(c), c.frames = count("a frame count");
      if (c.mods) throw fail("'hold' takes a key without modifiers");
    } else if (word == "click") {
      c.kind = K::click, c.button = button(), c.x0 = number("X"), c.y0 = number("Y");
    } else if (word == "drag") {
      c.kind = K::drag, c.button = button();
      c.x0 = number("X0"), c.y0 = number("Y0"), c.x1 = number("X1"), c.y1 = number("Y1");
      c.frames = 10;
      std::string peek;
      if (words >> peek) {
        words.clear();
        words.str(peek);
        c.frames = count("FRAMES");
        if (c.frames < 1) throw fail("'drag' needs at least 1 frame");
      }
    } else if (word == "move") {
      c.kind = K::move, c.x0 = number("X"), c.y0 = number("Y");
    } else if (word == "resize") {
      c.kind = K::resize, c.x0 = number("W"), c.y0 = number("H");
      if (c.x0 < 1 || c.y0 < 1 || c.x0 > 16384 || c.y0 > 16384 || c.x0 != std::floor(c.x0) || c.y0 != std::floor(c.y0))
        throw fail("'resize' needs whole numbers in 1..16384");
    } else if (word == "scroll") {
      c.kind = K::scroll, c.scroll = number("DY");
    } else if (word == "screenshot" || word == "window-screenshot") {
      c.kind = word == "screenshot" ? K::screenshot : K::window_screenshot;
      if (!(words >> c.file)) throw fail("'" + word + "' needs a file name");
    } else if (word == "quit") {
      c.kind = K::quit;
    } else {
      throw fail("unknown command '" + word + "'");
    }
    std::string extra;
    if (words >> extra) throw fail("unexpected '" + extra + "' after '" + word + "'");
    commands.push_back(std::move(c));
  }
  return commands;
}

std::vector<ScriptCommand> read_script(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error(file.string() + ": cannot open");
  std::stringstream text;
  text << in.rdbuf();
  return parse_script(text.str(), file.string());
}

}  // namespace epi::viewer

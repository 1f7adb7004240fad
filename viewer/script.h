// Scripted sessions (`epi-viewer SCENE --script FILE`): one command a line, `#` comments.
//   wait N                              N frames of the window
//   key NAME                            press and release a key: a GLFW key name (F, ESCAPE, F3, 1, ...)
//                                       with optional CTRL+, SHIFT+, ALT+ prefixes (CTRL+1)
//   hold NAME N                         hold a key down for N frames (fly: W, A, S, D, Q, E)
//   click BUTTON X Y                    BUTTON: left, middle or right; window pixels
//   drag BUTTON X0 Y0 X1 Y1 [FRAMES]    press, move over FRAMES frames (default 10), release
//   move X Y                            move the pointer (hover: the reachability view's pixel)
//   scroll DY                           wheel steps (positive: towards the scene)
//   resize W H                          resize the window (screen coordinates); the renderer follows
//   screenshot FILE                     the rendered image (as `epi render -o FILE` writes it)
//   window-screenshot FILE              the whole window, panel included (PNG)
//   quit                                exit (also the end of the script)
// Parsing checks everything before the window opens; errors are "<file>:<line>: <problem>".
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace epi::viewer {

enum class Button { left, middle, right };

struct ScriptCommand {
  enum class Kind { wait, key, hold, click, drag, move, scroll, resize, screenshot, window_screenshot, quit } kind = Kind::wait;
  int line = 0;
  int frames = 0;       // wait, hold, drag
  int key = 0;          // key, hold: the GLFW key code
  int mods = 0;         // key: GLFW modifier bits
  std::string name;     // key, hold: as written
  Button button = Button::left;
  float x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // click (x0, y0), drag, move (x0, y0), resize (width x0, height y0)
  float scroll = 0;
  std::string file;     // screenshot
};

// The GLFW key code of a GLFW key name (glfw3.h's GLFW_KEY_<NAME>), -1 if unknown.
int key_code(std::string_view name);

std::vector<ScriptCommand> parse_script(std::string_view text, const std::string& source);
std::vector<ScriptCommand> read_script(const std::filesystem::path& file);

}  // namespace epi::viewer

#include "devices/discover.h"

#include "devices/alsa_seq.h"
#include "devices/backends.h"
#include "devices/util.h"

#include <SDL.h>
#include <alsa/asoundlib.h>
#include <fcntl.h>
#include <gpiod.h>
#include <hidapi/hidapi.h>
#include <libevdev/libevdev.h>
#include <libusb-1.0/libusb.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace mar {
namespace {

std::string profile_of(const std::vector<ProfileId>& profiles, int vid, int pid) {
  for (const auto& p : profiles)
    if (p.vid == vid)
      for (int q : p.pids)
        if (q == pid) return p.name;
  return {};
}

void access_status(FoundDevice& f) {
  if (access(f.node.c_str(), R_OK | W_OK) == 0) {
    f.status = "available";
  } else {
    f.status = "permission denied";
    f.problem = "install " + std::string(kUdevRule) + " and join the 'marionette' group";
  }
}

BackendReport usb_midi(const std::vector<ProfileId>& profiles) {
  BackendReport r{"usb_midi", "ok", {}};
  libusb_context* ctx = nullptr;
  if (libusb_init(&ctx) != 0) return {"usb_midi", "libusb could not start", {}};
  libusb_device** list = nullptr;
  const ssize_t n = libusb_get_device_list(ctx, &list);
  for (ssize_t i = 0; i < n; ++i) {
    libusb_device_descriptor dd{};
    libusb_config_descriptor* cfg = nullptr;
    if (libusb_get_device_descriptor(list[i], &dd) != 0 || libusb_get_active_config_descriptor(list[i], &cfg) != 0) continue;
    bool midi = false;
    for (int k = 0; k < cfg->bNumInterfaces; ++k)
      for (int a = 0; a < cfg->interface[k].num_altsetting; ++a)
        midi = midi || (cfg->interface[k].altsetting[a].bInterfaceClass == LIBUSB_CLASS_AUDIO &&
                        cfg->interface[k].altsetting[a].bInterfaceSubClass == 3);
    libusb_free_config_descriptor(cfg);
    if (!midi) continue;
    FoundDevice f;
    f.backend = "usb_midi";
    f.identity = devutil::vid_pid(dd.idVendor, dd.idProduct) + " USB-MIDI";
    char node[64];
    std::snprintf(node, sizeof node, "/dev/bus/usb/%03d/%03d", libusb_get_bus_number(list[i]), libusb_get_device_address(list[i]));
    f.node = node;
    f.profile = profile_of(profiles, dd.idVendor, dd.idProduct);
    access_status(f);
    r.found.push_back(f);
  }
  if (n >= 0) libusb_free_device_list(list, 1);
  libusb_exit(ctx);
  return r;
}

BackendReport hid(const std::vector<ProfileId>& profiles) {
  BackendReport r{"hid", "ok", {}};
  if (hid_init() != 0) return {"hid", "hidapi could not start", {}};
  hid_device_info* list = hid_enumerate(0, 0);
  for (const hid_device_info* d = list; d; d = d->next) {
    FoundDevice f;
    f.backend = "hid";
    char usage[32] = "";
    if (d->usage_page) std::snprintf(usage, sizeof usage, " usage %04x:%04x", d->usage_page, d->usage);
    f.identity = devutil::vid_pid(d->vendor_id, d->product_id) + " '" + devutil::narrow(d->product_string) + "'" +
                 (d->serial_number && *d->serial_number ? " serial " + devutil::narrow(d->serial_number) : "") + usage;
    f.node = d->path;
    f.profile = profile_of(profiles, d->vendor_id, d->product_id);
    access_status(f);
    r.found.push_back(f);
  }
  hid_free_enumeration(list);
  return r;
}

BackendReport gpio() {
  BackendReport r{"gpio", "ok", {}};
  std::vector<std::string> seen;
  for (const char* dir : {"/sys/bus/gpio/devices", "/sys/class/gpio"})
    for (const std::string& n : devutil::list_dir(dir)) {
      if (n.rfind("gpiochip", 0) != 0 || std::find(seen.begin(), seen.end(), n) != seen.end()) continue;
      seen.push_back(n);
      FoundDevice f;
      f.backend = "gpio";
      f.node = "/dev/" + n;
      if (gpiod_chip* c = gpiod_chip_open(f.node.c_str())) {
        f.identity = n + " '" + gpiod_chip_label(c) + "' " + std::to_string(gpiod_chip_num_lines(c)) + " lines";
        gpiod_chip_close(c);
        f.status = "available";
      } else {
        f.identity = n;
        access_status(f);
        if (f.status == "available") {
          f.status = "unreadable";
          f.problem = "libgpiod cannot open it";
        }
      }
      r.found.push_back(f);
    }
  return r;
}

BackendReport tablets() {
  BackendReport r{"tablet", "ok", {}};
  for (const std::string& name : devutil::list_dir("/sys/class/input")) {
    if (name.rfind("event", 0) != 0) continue;
    FoundDevice f;
    f.backend = "tablet";
    f.node = "/dev/input/" + name;
    const int fd = ::open(f.node.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
      f.identity = devutil::read_line("/sys/class/input/" + name + "/device/name");
      if (f.identity.empty()) continue;
      access_status(f);
      r.found.push_back(f);
      continue;
    }
    libevdev* d = nullptr;
    if (libevdev_new_from_fd(fd, &d) == 0) {
      const bool pen = libevdev_has_event_code(d, EV_ABS, ABS_X) &&
                       (libevdev_has_event_code(d, EV_KEY, BTN_TOOL_PEN) || libevdev_has_event_code(d, EV_ABS, ABS_PRESSURE));
      if (pen) {
        f.identity = devutil::vid_pid(libevdev_get_id_vendor(d), libevdev_get_id_product(d)) + " '" +
                     (libevdev_get_name(d) ? libevdev_get_name(d) : "") + "'";
        f.status = "available";
        r.found.push_back(f);
      }
      libevdev_free(d);
    }
    ::close(fd);
  }
  return r;
}

BackendReport alsa() {
  snd_seq_t* seq = nullptr;
  quiet_alsa_errors();
  const int rc = snd_seq_open(&seq, "default", SND_SEQ_OPEN_INPUT, SND_SEQ_NONBLOCK);
  if (rc < 0) return {"alsa", std::string("no ALSA sequencer (/dev/snd/seq: ") + snd_strerror(rc) + ")", {}};
  BackendReport r{"alsa", "ok", {}};
  snd_seq_client_info_t* ci = nullptr;
  snd_seq_port_info_t* pi = nullptr;
  snd_seq_client_info_malloc(&ci);
  snd_seq_port_info_malloc(&pi);
  snd_seq_client_info_set_client(ci, -1);
  while (snd_seq_query_next_client(seq, ci) >= 0) {
    const int client = snd_seq_client_info_get_client(ci);
    if (client == SND_SEQ_CLIENT_SYSTEM) continue;
    snd_seq_port_info_set_client(pi, client);
    snd_seq_port_info_set_port(pi, -1);
    while (snd_seq_query_next_port(seq, pi) >= 0) {
      const unsigned caps = snd_seq_port_info_get_capability(pi);
      if ((caps & (SND_SEQ_PORT_CAP_READ | SND_SEQ_PORT_CAP_SUBS_READ)) != (SND_SEQ_PORT_CAP_READ | SND_SEQ_PORT_CAP_SUBS_READ))
        continue;
      FoundDevice f;
      f.backend = "alsa";
      f.identity = std::to_string(client) + ":" + std::to_string(snd_seq_port_info_get_port(pi)) + " '" +
                   snd_seq_client_info_get_name(ci) + "' / '" + snd_seq_port_info_get_name(pi) + "'";
      f.node = "/dev/snd/seq";
      f.status = "available";
      r.found.push_back(f);
    }
  }
  snd_seq_port_info_free(pi);
  snd_seq_client_info_free(ci);
  snd_seq_close(seq);
  return r;
}

BackendReport sdl_pads() {
  BackendReport r{"sdl", "ok", {}};
  if (SDL_InitSubSystem(SDL_INIT_GAMECONTROLLER) != 0) return {"sdl", std::string("SDL: ") + SDL_GetError(), {}};
  for (int i = 0; i < SDL_NumJoysticks(); ++i) {
    if (!SDL_IsGameController(i)) continue;
    FoundDevice f;
    f.backend = "sdl";
    const char* name = SDL_GameControllerNameForIndex(i);
    f.identity = devutil::vid_pid(SDL_JoystickGetDeviceVendor(i), SDL_JoystickGetDeviceProduct(i)) + " game controller '" +
                 (name ? name : "?") + "'";
    f.status = "available";
    r.found.push_back(f);
  }
  SDL_QuitSubSystem(SDL_INIT_GAMECONTROLLER);
  return r;
}

}  // namespace

std::vector<BackendReport> discover_devices(const std::vector<ProfileId>& profiles) {
  return {usb_midi(profiles), hid(profiles), gpio(), tablets(), alsa(), sdl_pads(),
          BackendReport{"osc", "ok (listens on 127.0.0.1 when a show binds OSC addresses)", {}}};
}

}  // namespace mar

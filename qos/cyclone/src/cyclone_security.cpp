// DDS-Security on Cyclone DDS 0.10: its builtin plugins, loaded per
// participant through QoS properties (the domain configuration stays the
// same for secured and unsecured participants of one process).
#include <new>
#include <utility>

#include "mtc/qos/cyclone_qos.hpp"

namespace mtc::qos {

namespace {

// Cyclone's builtin plugin of each kind: library, then its entry points.
struct Plugin {
  const char* kind;  // the property prefix: dds.sec.<kind>.library.*
  const char* library;
  const char* init;
  const char* finalize;
};
constexpr Plugin kPlugins[] = {
    {"auth", "dds_security_auth", "init_authentication", "finalize_authentication"},
    {"access", "dds_security_ac", "init_access_control", "finalize_access_control"},
    {"crypto", "dds_security_crypto", "init_crypto", "finalize_crypto"},
};

// A plugin by path ("<dir>/lib<name>.so") or, with no directory, by name,
// which Cyclone turns into lib<name>.so on the loader's search path.
std::string plugin_path(const std::string& plugin_dir, const char* library) {
  if (plugin_dir.empty()) return library;
  return plugin_dir + "/lib" + library + ".so";
}

}  // namespace

CycloneQos cyclone_security_qos(const std::string& dir, const std::string& plugin_dir) {
  CycloneQos qos(dds_create_qos());
  if (!qos) throw std::bad_alloc();
  const std::string uri = "file:" + dir + "/";
  const std::pair<const char*, std::string> files[] = {
      {"dds.sec.auth.identity_ca", uri + "ca.pem"},
      {"dds.sec.auth.identity_certificate", uri + "cert.pem"},
      {"dds.sec.auth.private_key", uri + "key.pem"},
      {"dds.sec.access.permissions_ca", uri + "ca.pem"},
      {"dds.sec.access.governance", uri + "governance.p7s"},
      {"dds.sec.access.permissions", uri + "permissions.p7s"},
  };
  for (const auto& [name, value] : files) dds_qset_prop(qos.get(), name, value.c_str());
  for (const auto& plugin : kPlugins) {
    const std::string prefix = std::string("dds.sec.") + plugin.kind + ".library.";
    dds_qset_prop(qos.get(), (prefix + "path").c_str(),
                  plugin_path(plugin_dir, plugin.library).c_str());
    dds_qset_prop(qos.get(), (prefix + "init").c_str(), plugin.init);
    dds_qset_prop(qos.get(), (prefix + "finalize").c_str(), plugin.finalize);
  }
  return qos;
}

std::string cyclone_security_plugin_dir() {
#ifdef MTC_CYCLONE_SECURITY_PLUGIN_DIR
  return MTC_CYCLONE_SECURITY_PLUGIN_DIR;
#else
  return {};
#endif
}

}  // namespace mtc::qos

#!/usr/bin/env bash
# Generates the DDS-Security files of a cell from a cell description: a
# certificate authority, one identity per device, observer (bridge) and tool,
# a signed governance document and each identity's signed permissions.
#
# Usage: scripts/security/make-pki.sh --cell FILE --out DIR [options]
#   --cell FILE           cell description (format below; scripts/security/cell.txt is the
#                         simulated cell of apps/cell)
#   --out DIR             output: DIR/ca/ (CA key and certificate, keep private) and one
#                         directory per identity, DIR/<name>/, which is what --security takes
#   --ca DIR              reuse the CA in DIR (ca.pem, ca_key.pem) instead of creating one
#   --not-before STAMP    validity of the identity certificates, YYYYMMDDHHMMSSZ
#   --not-after STAMP     (default: from now for 365 days)
#   --days N              identity validity in days when --not-after is not given
#   -h, --help            this text
#
# Cell description, one entry a line ('#' starts a comment):
#   device <uuid> [requests=<svc,...>] [provides=<svc,...>] [reads=<uuid,...>|*]
#                 [publishes=door,chuck]
#   observer <name>        read-only identity (the bridge, `mtc watch`)
# Services are the Part 5 names in lower case (material_load, open_door, ...).
# Interaction topics are one per service and side (mtc/InteractionRequest/
# MATERIAL_LOAD, mtc/InteractionResponse/MATERIAL_LOAD, ...): a device may
# publish the REQUEST topics of the services it requests and the RESPONSE
# topics of those it provides, nothing else, always in its own partition
# mtc/dev/<uuid>, plus its announcement, interface, heartbeat (and door /
# chuck) state there; it reads every topic in the partitions of `reads`
# (`*`: any device, for counterparts left to discovery). Observers read all.
#
# Each identity directory holds ca.pem (identity and permissions CA),
# cert.pem, key.pem, governance.p7s and permissions.p7s (S/MIME signed by
# the CA, as DDS-Security requires). DIR/authentication-order.txt lists the
# identities in the order they begin DDS-Security authentications, which a
# cell mixing Fast DDS and Cyclone DDS must respect (docs/security.md).
# Exit code 2 on bad usage or a bad cell description.
set -euo pipefail
set -f  # lists are split on commas below; `reads=*` must stay a '*'
usage() { awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "${BASH_SOURCE[0]}"; }
usage_error() { echo "make-pki.sh: $*" >&2; usage >&2; exit 2; }
need_value() { [ $# -ge 2 ] && [ -n "$2" ] || usage_error "$1 needs a value"; }

cell="" out="" ca_dir="" not_before="" not_after="" days=365
while [ $# -gt 0 ]; do
  case "$1" in
    -h | --help) usage; exit 0 ;;
    --cell) need_value "$@"; cell="$2"; shift 2 ;;
    --out) need_value "$@"; out="$2"; shift 2 ;;
    --ca) need_value "$@"; ca_dir="$2"; shift 2 ;;
    --not-before) need_value "$@"; not_before="$2"; shift 2 ;;
    --not-after) need_value "$@"; not_after="$2"; shift 2 ;;
    --days) need_value "$@"; days="$2"; shift 2 ;;
    *) usage_error "unknown option '$1'" ;;
  esac
done
[ -n "$cell" ] || usage_error "--cell is required"
[ -n "$out" ] || usage_error "--out is required"
[ -r "$cell" ] || usage_error "cannot read cell description '$cell'"
[[ "$days" =~ ^[1-9][0-9]*$ ]] || usage_error "--days needs a positive number, not '$days'"
for stamp in "$not_before" "$not_after"; do
  [ -z "$stamp" ] || [[ "$stamp" =~ ^[0-9]{14}Z$ ]] ||
    usage_error "dates are YYYYMMDDHHMMSSZ, not '$stamp'"
done
command -v openssl >/dev/null || { echo "make-pki.sh: openssl is not installed" >&2; exit 1; }

# ------------------------------------------------------ cell description
id_re='^[A-Za-z0-9_.:-]{1,64}$'
services='material_feed material_change material_retract part_change material_load material_unload open_door close_door open_chuck close_chuck'
names=() kinds=() requests=() provides=() reads=() publishes=()
line_no=0
bad_cell() { echo "make-pki.sh: $cell:$line_no: $*" >&2; exit 2; }
check_services() {
  local s
  for s in ${1//,/ }; do
    [[ " $services " == *" $s "* ]] || bad_cell "unknown service '$s' (known: $services)"
  done
}
while IFS= read -r line || [ -n "$line" ]; do
  line_no=$((line_no + 1))
  line="${line%%#*}"
  read -r -a words <<<"$line"
  [ ${#words[@]} -gt 0 ] || continue
  kind="${words[0]}" name="${words[1]:-}"
  [[ "$name" =~ $id_re ]] || bad_cell "'$name' is not a valid device uuid or name"
  for n in "${names[@]}"; do [ "$n" != "$name" ] || bad_cell "'$name' described twice"; done
  req="" prov="" rd="" pub=""
  case "$kind" in
    device)
      for w in "${words[@]:2}"; do
        case "$w" in
          requests=*) req="${w#requests=}"; check_services "$req" ;;
          provides=*) prov="${w#provides=}"; check_services "$prov" ;;
          reads=*) rd="${w#reads=}"
            for r in ${rd//,/ }; do
              [ "$r" = "*" ] || [[ "$r" =~ $id_re ]] || bad_cell "reads= takes device uuids or *, not '$r'"
            done ;;
          publishes=*) pub="${w#publishes=}"
            for p in ${pub//,/ }; do
              [ "$p" = door ] || [ "$p" = chuck ] || bad_cell "publishes= takes door,chuck, not '$p'"
            done ;;
          *) bad_cell "unknown field '$w'" ;;
        esac
      done ;;
    observer) [ ${#words[@]} -eq 2 ] || bad_cell "an observer has a name only" ;;
    *) bad_cell "unknown entry '$kind' (device or observer)" ;;
  esac
  names+=("$name") kinds+=("$kind") requests+=("$req") provides+=("$prov")
  reads+=("$rd") publishes+=("$pub")
done <"$cell"
[ ${#names[@]} -gt 0 ] || bad_cell "describes no identity"

# ------------------------------------------------------------------- CA
mkdir -p "$out"
out="$(cd "$out" && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
if [ -n "$ca_dir" ]; then
  [ -r "$ca_dir/ca.pem" ] && [ -r "$ca_dir/ca_key.pem" ] ||
    usage_error "--ca $ca_dir has no ca.pem and ca_key.pem"
  if [ "$(cd "$ca_dir" && pwd)" != "$out/ca" ]; then
    mkdir -p "$out/ca" && cp "$ca_dir/ca.pem" "$ca_dir/ca_key.pem" "$out/ca/"
  fi
else
  mkdir -p "$out/ca"
  openssl req -x509 -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes -sha256 \
    -keyout "$out/ca/ca_key.pem" -out "$out/ca/ca.pem" -days 3650 \
    -subj "/O=mtconnect-dds/CN=mtconnect-dds cell CA" 2>"$work/log" ||
    { cat "$work/log" >&2; exit 1; }
  chmod 600 "$out/ca/ca_key.pem"
fi
ca="$out/ca/ca.pem"
ca_key="$out/ca/ca_key.pem"

# openssl ca takes explicit validity dates (x509 -req only takes days).
cat >"$work/ca.cnf" <<EOF
[ca]
default_ca = cell
[cell]
database = $work/index.txt
new_certs_dir = $work
serial = $work/serial
default_md = sha256
policy = any
unique_subject = no
copy_extensions = none
[any]
organizationName = supplied
commonName = supplied
EOF
: >"$work/index.txt"
openssl rand -hex 16 >"$work/serial"
validity=()
[ -n "$not_before" ] && validity+=(-startdate "$not_before")
if [ -n "$not_after" ]; then validity+=(-enddate "$not_after"); else validity+=(-days "$days"); fi

sign() { # file.xml -> file.p7s, S/MIME signed by the CA
  openssl smime -sign -text -in "$1" -out "${1%.xml}.p7s" -signer "$ca" -inkey "$ca_key" \
    2>"$work/log" || { cat "$work/log" >&2; exit 1; }
  rm -f "$1"
}

# ------------------------------------------------------------ governance
# Domains 0-230: DDS allows 232, but Cyclone DDS 0.10's access control
# refuses a governance or permissions document naming an id above 230 ("Can
# not parse governance file"), and one PKI secures both middlewares.
governance() {
  cat <<'EOF'
<?xml version="1.0" encoding="utf-8"?>
<!-- mtconnect-dds cell governance (generated by scripts/security/make-pki.sh) -->
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"
     xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-Security/20170801/omg_shared_ca_governance.xsd">
  <domain_access_rules>
    <domain_rule>
      <domains><id_range><min>0</min><max>230</max></id_range></domains>
      <allow_unauthenticated_participants>false</allow_unauthenticated_participants>
      <enable_join_access_control>true</enable_join_access_control>
      <discovery_protection_kind>ENCRYPT</discovery_protection_kind>
      <liveliness_protection_kind>ENCRYPT</liveliness_protection_kind>
      <rtps_protection_kind>NONE</rtps_protection_kind>
      <topic_access_rules>
        <topic_rule>
          <topic_expression>*</topic_expression>
          <enable_discovery_protection>true</enable_discovery_protection>
          <enable_liveliness_protection>true</enable_liveliness_protection>
          <enable_read_access_control>true</enable_read_access_control>
          <enable_write_access_control>true</enable_write_access_control>
          <metadata_protection_kind>ENCRYPT</metadata_protection_kind>
          <data_protection_kind>ENCRYPT</data_protection_kind>
        </topic_rule>
      </topic_access_rules>
    </domain_rule>
  </domain_access_rules>
</dds>
EOF
}

# ----------------------------------------------------------- permissions
topic_list() { local t; for t in "$@"; do printf '          <topic>%s</topic>\n' "$t"; done; }
partition_list() { local p; for p in "$@"; do printf '          <partition>%s</partition>\n' "$p"; done; }

# permissions <index> <not_before> <not_after>: the grant of one identity.
permissions() {
  local i="$1" name="${names[$1]}" pub_topics=() sub_partitions=() r s
  if [ "${kinds[$i]}" = device ]; then
    pub_topics=(mtc/DeviceDescription mtc/InterfaceState mtc/Heartbeat)
    for s in ${requests[$i]//,/ }; do pub_topics+=("mtc/InteractionRequest/${s^^}"); done
    for s in ${provides[$i]//,/ }; do pub_topics+=("mtc/InteractionResponse/${s^^}"); done
    [[ ",${publishes[$i]}," == *,door,* ]] && pub_topics+=(mtc/DoorState)
    [[ ",${publishes[$i]}," == *,chuck,* ]] && pub_topics+=(mtc/ChuckState)
    for r in ${reads[$i]//,/ }; do
      if [ "$r" = "*" ]; then sub_partitions+=("mtc/dev/*"); else sub_partitions+=("mtc/dev/$r"); fi
    done
  else
    sub_partitions=("*")  # the DomainObserver reads every partition
  fi
  cat <<EOF
<?xml version="1.0" encoding="utf-8"?>
<!-- permissions of $name (generated by scripts/security/make-pki.sh) -->
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"
     xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-Security/20170801/omg_shared_ca_permissions.xsd">
  <permissions>
    <grant name="$name">
      <subject_name>CN=$name,O=mtconnect-dds</subject_name>
      <validity><not_before>$2</not_before><not_after>$3</not_after></validity>
      <allow_rule>
        <domains><id_range><min>0</min><max>230</max></id_range></domains>
EOF
  if [ ${#pub_topics[@]} -gt 0 ]; then
    printf '        <publish>\n          <topics>\n'
    topic_list "${pub_topics[@]}"
    printf '          </topics>\n          <partitions>\n'
    partition_list "mtc/dev/$name"
    printf '          </partitions>\n        </publish>\n'
  fi
  if [ ${#sub_partitions[@]} -gt 0 ]; then
    printf '        <subscribe>\n          <topics>\n'
    topic_list "mtc/*"
    printf '          </topics>\n          <partitions>\n'
    partition_list "${sub_partitions[@]}"
    printf '          </partitions>\n        </subscribe>\n'
  fi
  cat <<EOF
      </allow_rule>
      <default>DENY</default>
    </grant>
  </permissions>
</dds>
EOF
}

# ------------------------------------------------------------ identities
governance >"$work/governance.xml"
sign "$work/governance.xml"
# Permissions are valid as long as the CA; the identity certificate bounds
# an identity's life (rotation: a new certificate, same permissions).
perm_from="$(date -u -d '-1 day' +%Y-%m-%dT%H:%M:%S)"
perm_to="$(date -u -d '+3650 days' +%Y-%m-%dT%H:%M:%S)"
for i in "${!names[@]}"; do
  name="${names[$i]}"
  dir="$out/$name"
  mkdir -p "$dir"
  openssl req -new -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes -sha256 \
    -keyout "$dir/key.pem" -out "$work/$name.csr" -subj "/O=mtconnect-dds/CN=$name" \
    2>"$work/log" || { cat "$work/log" >&2; exit 1; }
  chmod 600 "$dir/key.pem"
  openssl ca -batch -notext -config "$work/ca.cnf" -cert "$ca" -keyfile "$ca_key" \
    "${validity[@]}" -in "$work/$name.csr" -out "$dir/cert.pem" 2>"$work/log" ||
    { cat "$work/log" >&2; exit 1; }
  cp "$ca" "$dir/ca.pem"
  cp "$work/governance.p7s" "$dir/governance.p7s"
  permissions "$i" "$perm_from" "$perm_to" >"$work/permissions.xml"
  sign "$work/permissions.xml"
  mv "$work/permissions.p7s" "$dir/permissions.p7s"
  echo "make-pki.sh: $dir (${kinds[$i]})"
done

# ------------------------------------------------- authentication order
# Which of two identities begins their DDS-Security authentication: each
# participant's GUID starts with the SHA-256 of its certificate subject
# (DER), and the lower begins. That matters in a cell that mixes Fast DDS
# 2.9 and Cyclone DDS 0.10: they meet only when the Cyclone side begins
# (docs/security.md). Written to DIR/authentication-order.txt, first begins.
subject_sha256() {
  local span offset length
  # The subject is the fifth field of the certificate body, after the
  # serial, the signature algorithm, the issuer and the validity ([0], the
  # version, is skipped).
  span="$(openssl asn1parse -in "$1" | awk '/d=2/ && !/cont \[ 0 \]/ {
      if (++n == 5) {
        match($0, /^ *[0-9]+/); offset = substr($0, RSTART, RLENGTH) + 0
        match($0, /hl= *[0-9]+/); header = substr($0, RSTART + 3, RLENGTH - 3) + 0
        match($0, / l= *[0-9]+/); body = substr($0, RSTART + 3, RLENGTH - 3) + 0
        print offset, header + body
      } }')"  # awk reads to the end: no SIGPIPE for openssl under pipefail
  read -r offset length <<<"$span"
  openssl x509 -in "$1" -outform DER | tail -c +$((offset + 1)) | head -c "$length" |
    sha256sum | cut -d' ' -f1
}
for name in "${names[@]}"; do
  echo "$(subject_sha256 "$out/$name/cert.pem") $name"
done | sort | cut -d' ' -f2 >"$out/authentication-order.txt"
echo "make-pki.sh: authentication order, first begins (a Cyclone DDS identity must come" \
  "before its Fast DDS peers, docs/security.md): $(paste -sd' ' "$out/authentication-order.txt")"

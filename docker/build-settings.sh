# shellcheck shell=bash disable=SC2034  # sets variables for the script that sources it
# Proxy and extra CA for the image builds, shared by scripts/up and scripts/drive (sourced; bash).
#
#   build_settings ROOT   sets build_args (--build-arg pairs) and build_settings_said (what to
#                         tell the user); returns 1 with build_settings_error set when
#                         TESTBED_EXTRA_CA names no PEM certificate.
#
# Proxy: HTTP_PROXY, HTTPS_PROXY and NO_PROXY of the environment go to every build as Docker's
# predefined build args, in both cases whichever is set (apt reads only the lower-case ones).
# Extra CA: the PEM file TESTBED_EXTRA_CA names is copied to docker/extra-ca/, which the
# Dockerfile's base stage trusts before apt runs; unset, that copy is removed.
build_settings() {
  local root=$1 upper lower up_value low_value names=()
  build_args=()
  build_settings_said=()
  build_settings_error=""
  for upper in HTTP_PROXY HTTPS_PROXY NO_PROXY; do
    lower=${upper,,}
    up_value=${!upper:-${!lower:-}}
    low_value=${!lower:-${!upper:-}}
    if [[ -n $up_value ]]; then
      build_args+=(--build-arg "$upper=$up_value" --build-arg "$lower=$low_value")
      names+=("$upper" "$lower")
    fi
  done
  ((${#names[@]})) &&
    build_settings_said+=("image builds get the proxy settings of the environment: ${names[*]}")
  local copy=$root/docker/extra-ca/from-TESTBED_EXTRA_CA.crt
  if [[ -z ${TESTBED_EXTRA_CA:-} ]]; then
    rm -f "$copy"
    return 0
  fi
  if [[ ! -f $TESTBED_EXTRA_CA || ! -r $TESTBED_EXTRA_CA ]]; then
    build_settings_error="TESTBED_EXTRA_CA=$TESTBED_EXTRA_CA: no such readable file (a PEM CA certificate)"
    return 1
  fi
  if ! grep -q -e '-----BEGIN CERTIFICATE-----' "$TESTBED_EXTRA_CA"; then
    build_settings_error="TESTBED_EXTRA_CA=$TESTBED_EXTRA_CA: not a PEM certificate (no BEGIN CERTIFICATE line); a DER file converts with: openssl x509 -inform der -in FILE -out FILE.crt"
    return 1
  fi
  install -m 644 "$TESTBED_EXTRA_CA" "$copy" || {
    build_settings_error="cannot copy TESTBED_EXTRA_CA=$TESTBED_EXTRA_CA to $copy"
    return 1
  }
  build_settings_said+=("image builds trust the extra CA $TESTBED_EXTRA_CA")
}

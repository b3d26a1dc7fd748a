/* libFuzzer harness for the protocol parsers (untrusted network input): the
 * first byte picks the parser — request JSON, WebSocket client message, query
 * string or binary frame — and the rest is its input. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "messages.h"
#include "request.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* Contract of every failing call: a code and a message that says why. */
static void check_error(int rc, const lc_proto_error *err)
{
    if (rc < 0 && (!err->code[0] || !err->message[0]))
        abort();
}

/* Whatever parses must emit JSON that parses back. */
static void round_trip(const lc_request *r)
{
    json_t *j = lc_proto_request_to_json(r);
    char *text = lc_proto_dump(j);
    lc_request back;
    lc_proto_error err;
    if (!text || lc_proto_parse_request(text, strlen(text), NULL, &back, &err) != 0)
        abort();
    lc_request_release(&back);
    free(text);
    json_decref(j);
}

static void fuzz_query(const char *s, size_t n)
{
    char *copy = malloc(n + 1);
    memcpy(copy, s, n);
    copy[n] = '\0';
    lc_request r;
    lc_request_default(&r);
    lc_proto_error err;
    int rc = 0;
    char *save = NULL;
    for (char *pair = strtok_r(copy, "&", &save); pair && !rc; pair = strtok_r(NULL, "&", &save)) {
        char *eq = strchr(pair, '=');
        if (eq)
            *eq = '\0';
        rc = lc_proto_apply_query(&r, pair, eq ? eq + 1 : "", NULL, &err);
    }
    if (!rc)
        rc = lc_proto_validate_request(&r, NULL, &err);
    check_error(rc, &err);
    if (!rc)
        round_trip(&r);
    lc_request_release(&r); /* its layers, if a key set them */
    free(copy);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1)
        return 0;
    const char *text = (const char *)data + 1;
    size_t n = size - 1;
    lc_proto_error err;
    switch (data[0] % 4) {
    case 0: {
        lc_request r;
        int rc = lc_proto_parse_request(text, n, NULL, &r, &err);
        check_error(rc, &err);
        if (!rc)
            round_trip(&r);
        lc_request_release(&r);
        break;
    }
    case 1: {
        lc_client_msg m;
        int rc = lc_proto_parse_client_message(text, n, NULL, &m, &err);
        check_error(rc, &err);
        if (!rc && m.update) {
            lc_request r;
            lc_request_default(&r);
            rc = lc_proto_apply_request(m.update, NULL, &r, &err);
            check_error(rc, &err);
            lc_request_release(&r);
        }
        lc_client_msg_free(&m);
        break;
    }
    case 2: fuzz_query(text, n); break;
    case 3: {
        lc_frame_header h;
        const unsigned char *img;
        size_t img_len;
        int rc = lc_proto_unpack_frame((const unsigned char *)text, n, &h, &img, &img_len, &err);
        check_error(rc, &err);
        if (!rc && (img < (const unsigned char *)text || img + img_len != (const unsigned char *)text + n))
            abort();
        break;
    }
    }
    return 0;
}

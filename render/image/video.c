/* H.264/MP4 and VP9/WebM files from RGBA frames through libavcodec (video.h). */
#include "video.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#ifdef LUCENT_VIDEO
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>
#endif

static const struct {
    const char *name, *encoder, *ext, *mime;
} CODECS[] = {{"h264", "libx264", "mp4", "video/mp4"}, {"vp9", "libvpx-vp9", "webm", "video/webm"}};

int lc_video_codec_from_name(const char *name)
{
    for (int i = 0; i < 2; i++)
        if (name && strcmp(name, CODECS[i].name) == 0)
            return i;
    return -1;
}

const char *lc_video_codec_name(lc_video_codec c) { return CODECS[c].name; }

const char *lc_video_extension(lc_video_codec c) { return CODECS[c].ext; }

const char *lc_video_mime(lc_video_codec c) { return CODECS[c].mime; }

#ifndef LUCENT_VIDEO

bool lc_video_available(lc_video_codec c)
{
    (void)c;
    return false;
}

int lc_video_open(const char *path, lc_video_codec codec, int width, int height, int fps, lc_video **out, lc_error *err)
{
    (void)path, (void)codec, (void)width, (void)height, (void)fps;
    *out = NULL;
    return lc_err(err, LC_ERR_UNSUPPORTED, "built without libavcodec: no video encoding");
}

int lc_video_write(lc_video *v, const uint8_t *rgba, lc_error *err)
{
    (void)v, (void)rgba;
    return lc_err(err, LC_ERR_UNSUPPORTED, "built without libavcodec: no video encoding");
}

int lc_video_close(lc_video *v, lc_error *err)
{
    (void)v;
    return lc_err(err, LC_ERR_UNSUPPORTED, "built without libavcodec: no video encoding");
}

void lc_video_abort(lc_video *v) { (void)v; }

#else

struct lc_video {
    AVFormatContext *fmt;
    AVCodecContext *enc;
    AVStream *stream;
    struct SwsContext *sws;
    AVFrame *frame;
    AVPacket *pkt;
    int width, height;
    int64_t next_pts;
    bool header_written;
    char path[4096];
};

bool lc_video_available(lc_video_codec c) { return avcodec_find_encoder_by_name(CODECS[c].encoder) != NULL; }

static int av_fail(lc_error *err, int code, const char *what, int averr)
{
    char buf[AV_ERROR_MAX_STRING_SIZE] = "";
    av_strerror(averr, buf, sizeof buf);
    return lc_err(err, code, "%s: %s", what, buf);
}

static void video_free(lc_video *v)
{
    if (!v)
        return;
    if (v->fmt) {
        if (v->fmt->pb)
            avio_closep(&v->fmt->pb);
        avformat_free_context(v->fmt);
    }
    avcodec_free_context(&v->enc);
    sws_freeContext(v->sws);
    av_frame_free(&v->frame);
    av_packet_free(&v->pkt);
    free(v);
}

/* Sends frame (NULL = flush) and writes every packet the encoder gives back. */
static int encode(lc_video *v, AVFrame *frame, lc_error *err)
{
    int rc = avcodec_send_frame(v->enc, frame);
    if (rc < 0)
        return av_fail(err, LC_ERR_INTERNAL, "video encoder", rc);
    for (;;) {
        rc = avcodec_receive_packet(v->enc, v->pkt);
        if (rc == AVERROR(EAGAIN) || rc == AVERROR_EOF)
            return 0;
        if (rc < 0)
            return av_fail(err, LC_ERR_INTERNAL, "video encoder", rc);
        av_packet_rescale_ts(v->pkt, v->enc->time_base, v->stream->time_base);
        v->pkt->stream_index = v->stream->index;
        rc = av_interleaved_write_frame(v->fmt, v->pkt);
        if (rc < 0)
            return av_fail(err, LC_ERR_IO, v->path, rc);
    }
}

int lc_video_open(const char *path, lc_video_codec codec, int width, int height, int fps, lc_video **out, lc_error *err)
{
    *out = NULL;
    if ((int)codec < 0 || (int)codec > 1)
        return lc_err_field(err, LC_ERR_INVALID, "codec", "codec: unknown codec");
    if (width < 16 || height < 16 || width % 2 || height % 2)
        return lc_err_field(err, LC_ERR_INVALID, "width", "width, height: %d x %d; both must be even and >= 16", width,
                            height);
    if (fps < 1 || fps > 240)
        return lc_err_field(err, LC_ERR_INVALID, "fps", "fps: %d is outside [1, 240]", fps);
    av_log_set_level(AV_LOG_ERROR); /* the encoders' statistics would fill the daemon's log */
    const AVCodec *c = avcodec_find_encoder_by_name(CODECS[codec].encoder);
    if (!c)
        return lc_err_field(err, LC_ERR_UNSUPPORTED, "codec", "codec: this libavcodec has no %s encoder",
                            CODECS[codec].encoder);
    lc_video *v = calloc(1, sizeof *v);
    if (!v)
        return lc_err(err, LC_ERR_NOMEM, "out of memory");
    snprintf(v->path, sizeof v->path, "%s", path);
    v->width = width, v->height = height;
    int rc = avformat_alloc_output_context2(&v->fmt, NULL, CODECS[codec].ext, path);
    if (rc < 0 || !v->fmt) {
        video_free(v);
        return av_fail(err, LC_ERR_INTERNAL, "video container", rc);
    }
    v->stream = avformat_new_stream(v->fmt, NULL);
    v->enc = avcodec_alloc_context3(c);
    v->frame = av_frame_alloc();
    v->pkt = av_packet_alloc();
    if (!v->stream || !v->enc || !v->frame || !v->pkt) {
        video_free(v);
        return lc_err(err, LC_ERR_NOMEM, "out of memory");
    }
    v->enc->width = width;
    v->enc->height = height;
    v->enc->pix_fmt = AV_PIX_FMT_YUV420P;
    v->enc->time_base = (AVRational){1, fps};
    v->enc->framerate = (AVRational){fps, 1};
    v->enc->gop_size = 2 * fps;
    v->enc->thread_count = 1; /* the render workers own the cores */
    if (v->fmt->oformat->flags & AVFMT_GLOBALHEADER)
        v->enc->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
    /* Quality-driven rate control: line drawings on a flat background need few
     * bits, and a fixed bitrate would smear the thin ribbons in motion. */
    if (codec == LC_VIDEO_H264) {
        av_opt_set(v->enc->priv_data, "preset", "veryfast", 0);
        av_opt_set(v->enc->priv_data, "crf", "18", 0);
    } else {
        av_opt_set(v->enc->priv_data, "deadline", "realtime", 0);
        av_opt_set(v->enc->priv_data, "cpu-used", "8", 0);
        av_opt_set(v->enc->priv_data, "crf", "30", 0);
        v->enc->bit_rate = 0;
    }
    rc = avcodec_open2(v->enc, c, NULL);
    if (rc >= 0)
        rc = avcodec_parameters_from_context(v->stream->codecpar, v->enc);
    if (rc < 0) {
        video_free(v);
        return av_fail(err, LC_ERR_INTERNAL, "video encoder", rc);
    }
    v->stream->time_base = v->enc->time_base;
    v->stream->avg_frame_rate = v->enc->framerate;
    v->frame->format = AV_PIX_FMT_YUV420P;
    v->frame->width = width;
    v->frame->height = height;
    rc = av_frame_get_buffer(v->frame, 0);
    v->sws = sws_getContext(width, height, AV_PIX_FMT_RGBA, width, height, AV_PIX_FMT_YUV420P, SWS_BICUBIC, NULL, NULL,
                            NULL);
    if (rc < 0 || !v->sws) {
        video_free(v);
        return lc_err(err, LC_ERR_NOMEM, "video frame: out of memory");
    }
    rc = avio_open(&v->fmt->pb, path, AVIO_FLAG_WRITE);
    if (rc < 0) {
        video_free(v);
        return av_fail(err, LC_ERR_IO, path, rc);
    }
    rc = avformat_write_header(v->fmt, NULL);
    if (rc < 0) {
        video_free(v);
        unlink(path);
        return av_fail(err, LC_ERR_IO, path, rc);
    }
    v->header_written = true;
    *out = v;
    return 0;
}

int lc_video_write(lc_video *v, const uint8_t *rgba, lc_error *err)
{
    int rc = av_frame_make_writable(v->frame);
    if (rc < 0)
        return av_fail(err, LC_ERR_NOMEM, "video frame", rc);
    const uint8_t *src[1] = {rgba};
    int stride[1] = {4 * v->width};
    sws_scale(v->sws, src, stride, 0, v->height, v->frame->data, v->frame->linesize);
    v->frame->pts = v->next_pts++;
    return encode(v, v->frame, err);
}

int lc_video_close(lc_video *v, lc_error *err)
{
    int rc = encode(v, NULL, err);
    if (rc == 0) {
        int arc = av_write_trailer(v->fmt);
        if (arc < 0)
            rc = av_fail(err, LC_ERR_IO, v->path, arc);
    }
    if (rc == 0 && v->fmt->pb) {
        int arc = avio_closep(&v->fmt->pb);
        if (arc < 0)
            rc = av_fail(err, LC_ERR_IO, v->path, arc);
    }
    video_free(v);
    return rc;
}

void lc_video_abort(lc_video *v)
{
    if (!v)
        return;
    char path[sizeof v->path];
    memcpy(path, v->path, sizeof path);
    video_free(v);
    unlink(path);
}

#endif

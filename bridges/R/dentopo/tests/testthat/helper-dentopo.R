# Tests that run the command skip when it is not available; tests/test_bridges.py
# (the Python suite) runs these with DENTOPO set to the dentopo under test.
skip_without_dentopo <- function() {
  found <- tryCatch(dentopo::dentopo_command(), error = function(e) conditionMessage(e))
  if (length(found) == 1L && grepl("not found", found)) {
    skip(paste("dentopo command not available:", found))
  }
}

# A small closed mesh (an octahedron refined once, pushed onto the unit
# sphere) as an ASCII PLY file.
write_sphere_ply <- function(path) {
  v <- rbind(c(1, 0, 0), c(-1, 0, 0), c(0, 1, 0), c(0, -1, 0), c(0, 0, 1), c(0, 0, -1))
  f <- rbind(c(1, 3, 5), c(3, 2, 5), c(2, 4, 5), c(4, 1, 5),
             c(3, 1, 6), c(2, 3, 6), c(4, 2, 6), c(1, 4, 6))
  for (round in 1:2) {
    key <- character()
    faces <- NULL
    mid <- function(a, b) {
      k <- paste(sort(c(a, b)), collapse = "-")
      if (!is.na(i <- match(k, key))) return(nrow(v) - length(key) + i)
      p <- (v[a, ] + v[b, ]) / 2
      v <<- rbind(v, p / sqrt(sum(p^2)))
      key <<- c(key, k)
      nrow(v)
    }
    for (i in seq_len(nrow(f))) {
      a <- f[i, 1]; b <- f[i, 2]; c <- f[i, 3]
      ab <- mid(a, b); bc <- mid(b, c); ca <- mid(c, a)
      faces <- rbind(faces, c(a, ab, ca), c(ab, b, bc), c(ca, bc, c), c(ab, bc, ca))
    }
    f <- faces
  }
  lines <- c("ply", "format ascii 1.0", sprintf("element vertex %d", nrow(v)),
             "property float x", "property float y", "property float z",
             sprintf("element face %d", nrow(f)), "property list uchar int vertex_indices",
             "end_header", sprintf("%.9f %.9f %.9f", v[, 1], v[, 2], v[, 3]),
             sprintf("3 %d %d %d", f[, 1] - 1L, f[, 2] - 1L, f[, 3] - 1L))
  writeLines(lines, path)
  path
}

max_relative_difference <- function(got, want) {
  max(ifelse(want == 0, abs(got), abs(got - want) / abs(want)))
}

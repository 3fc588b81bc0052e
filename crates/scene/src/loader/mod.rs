//! Scene loaders: the caustica TOML format, OBJ and PLY meshes, and the built-in scenes.

"""Reading and writing: rig data files, tyre property files, safe outputs."""

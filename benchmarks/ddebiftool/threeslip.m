function threeslip(intervals,degree,seedfile)
%% The three-slip orbit at k = 18, tau = 10 (other parameters the defaults,
% d = 1e-4): period and Floquet multipliers from DDE-BIFTOOL's collocation.
% slopetui's `orbit --k 18 --tau 10 --delta 1e-6 --slips 3` uses delta = 1e-6
% only in the initial condition (eq. 19: all five variables = delta); it does
% not enter eqs. 6a-6e. The seed is only Newton's starting guess: one period
% of slopetui's equally spaced 3-slip seed (write_seed.py writes it:
% core.orbit_seed.n_slip_seed, before slopetui's own Newton). A seed from our
% own RK4 run in Octave to t = 600 (one slip cycle stretched to the mean
% spacing) did not work: the run's slips were still far from equal spacing
% (a near-neutral direction) and Newton went to the equilibrium.
if nargin<1, intervals=60; end
if nargin<2, degree=4; end
if nargin<3, seedfile='threeslip_seed.txt'; end
setup_path();
t0=tic;
[funcs,ip]=slope_funcs();
par=zeros(1,8);
par([ip.k,ip.tau,ip.c,ip.a,ip.b,ip.cc,ip.d,ip.v])=[18,10,0,3.2,7.2,4.8,1e-4,0.1];
s=linspace(0,1,intervals*degree+1);
S=load('-ascii',seedfile); t=S(:,1)'; X=S(:,2:6)';
fid=fopen(seedfile); hdr=fgetl(fid); fclose(fid);
P=sscanf(hdr(strfind(hdr,'seed_period=')+12:end),'%f');
tt=s*P;
fprintf('SEED %s: slopetui''s 3-slip seed, period %.8f\n',seedfile,P);
prof=zeros(5,numel(s));
for j=1:5, prof(j,:)=interp1(t,X(j,:),tt,'spline'); end
c=(prof(1,end)-prof(1,1))/P;
prof(1,:)=prof(1,:)-prof(1,1)-c*s*P;     % z = m_x - c t, pinned z(0)=0
par(ip.c)=c;
pt=dde_psol_create('parameter',par,'mesh',s,'degree',degree,'profile',prof,'period',P);
fprintf('SEED period %.6f, drift c=%.6f, mismatch of the ends %.1e\n',P,c,...
    norm(prof(2:end,end)-prof(2:end,1),inf));
mth=df_mthod(funcs,'psol');
mth.point.extra_condition=1;
mth.point.adapt_mesh_before_correct=1;
mth.point.adapt_mesh_after_correct=1;
mth.point.newton_max_iterations=20;
[pt,ok]=p_correc(funcs,pt,ip.c,[],mth.point,1);
if ~ok, error('Newton from the seed failed'); end
% a second correction on the mesh adapted to the corrected orbit
[pt,ok]=p_correc(funcs,pt,ip.c,[],mth.point,1);
if ~ok, error('second correction failed'); end
br=df_brnch(funcs,ip.c,'psol'); br.method=mth; br.point=pt;
[~,~,~,pts]=GetStability(br,'funcs',funcs,'exclude_trivial',false);
mu=pts(1).stability.mu(:);
% two multipliers are trivially 1 (the flow and the z-translation of the
% co-moving frame): the two closest to 1
[~,o]=sort(abs(mu-1)); triv=mu(o(1:2)); nontriv=mu(o(3:end));
[~,o2]=sort(abs(nontriv),'descend'); nontriv=nontriv(o2);
near=abs(abs(nontriv)-1)<1e-3;
fprintf('THREESLIP T=%.8f mu=%s\n',pt.period,mat2str(nontriv(1:6).',9));
fprintf('THREESLIP trivial: %s (|mu-1| %.1e, %.1e); nontrivial within 1e-3 of the unit circle: %d, |mu| %s, arg/(2 pi) %s; largest nontrivial |mu|=%.9f, next off the circle %.6f\n',...
    mat2str(triv.',12),abs(triv(1)-1),abs(triv(2)-1),sum(near),mat2str(abs(nontriv(near)).',9),...
    mat2str(angle(nontriv(near)).'/(2*pi),6),abs(nontriv(1)),abs(nontriv(find(~near,1))));
fprintf('THREESLIP k=18 tau=10 drift c=%.8f pp(m_y)=%.6f mesh %d x degree %d, runtime %.0fs\n',...
    pt.parameter(ip.c),max(pt.profile(2,:))-min(pt.profile(2,:)),intervals,degree,toc(t0));
save('-mat',sprintf('threeslip_%d.mat',intervals),'pt','mu');
if pt.parameter(ip.c)<1e-3, error('Newton went to the equilibrium (drift c=%.2e), not to an orbit',pt.parameter(ip.c)); end
end
